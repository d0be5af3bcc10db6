#include "treeskel/io/output_set.h"

#include "treeskel/error.h"
#include "treeskel/io/atomic_file.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <mutex>

namespace treeskel::io {

namespace fs = std::filesystem;

namespace {

// The staging folders alive in this process, for the signal handler: fixed storage, so the handler
// reads them without allocating.
constexpr int kSlots = 64;
constexpr std::size_t kPathBytes = 4096;
char g_folders[kSlots][kPathBytes];
std::atomic<bool> g_used[kSlots];
std::mutex g_table;  // taken by threads registering folders, never by the handler
struct sigaction g_previous[3];
constexpr int kSignals[3] = {SIGINT, SIGTERM, SIGHUP};

/// Empties and removes one staging folder with system calls only (safe in a signal handler).
void remove_folder_now(const char* path) {
  const int dir = ::open(path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    alignas(8) char buffer[8192];
    for (;;) {
      const long n = ::syscall(SYS_getdents64, dir, buffer, sizeof buffer);
      if (n <= 0) break;
      for (long at = 0; at < n;) {
        struct Entry {
          std::uint64_t inode;
          std::int64_t offset;
          unsigned short length;
          unsigned char type;
          char name[1];
        };
        const auto* e = reinterpret_cast<const Entry*>(buffer + at);
        if (std::strcmp(e->name, ".") != 0 && std::strcmp(e->name, "..") != 0) ::unlinkat(dir, e->name, 0);
        at += e->length;
      }
    }
    ::close(dir);
  }
  ::rmdir(path);
}

extern "C" void on_fatal_signal(int sig) {
  for (int i = 0; i < kSlots; ++i)
    if (g_used[i].load()) remove_folder_now(g_folders[i]);
  for (int k = 0; k < 3; ++k)
    if (kSignals[k] == sig) ::sigaction(sig, &g_previous[k], nullptr);
  ::raise(sig);
}

void install_handler_once() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (int k = 0; k < 3; ++k) {
      struct sigaction current {};
      ::sigaction(kSignals[k], nullptr, &current);
      g_previous[k] = current;
      if (current.sa_handler == SIG_IGN) continue;  // e.g. nohup: keep ignoring
      struct sigaction ours {};
      ours.sa_handler = on_fatal_signal;
      sigemptyset(&ours.sa_mask);
      ::sigaction(kSignals[k], &ours, nullptr);
    }
  });
}

int register_folder(const fs::path& folder) {
  const std::string text = folder.string();
  if (text.size() >= kPathBytes) return -1;
  std::lock_guard<std::mutex> lock(g_table);
  for (int i = 0; i < kSlots; ++i)
    if (!g_used[i].load()) {
      std::memcpy(g_folders[i], text.c_str(), text.size() + 1);
      g_used[i].store(true);
      return i;
    }
  return -1;  // beyond 64 folders at once a signal leaves that folder; nothing else is lost
}

void unregister_folder(const fs::path& folder) {
  std::lock_guard<std::mutex> lock(g_table);
  for (int i = 0; i < kSlots; ++i)
    if (g_used[i].load() && folder.string() == g_folders[i]) g_used[i].store(false);
}


}  // namespace

OutputSet::OutputSet(std::vector<fs::path> inputs) : inputs_(std::move(inputs)) { install_handler_once(); }

OutputSet::~OutputSet() {
  for (const auto& folder : folders_) {
    unregister_folder(folder);
    std::error_code ec;
    fs::remove_all(folder, ec);
  }
}

fs::path OutputSet::stage(const fs::path& target, const std::string& what) {
  const std::string named = what + " " + target.string();
  if (target.empty() || target.filename().empty() || target.filename() == "." || target.filename() == "..")
    throw OptionError(named + ": not a file name");
  const fs::path destination = write_destination(target);
  const fs::path dir = folder_of(destination);
  std::error_code ec;
  if (fs::is_directory(destination, ec)) throw OptionError(named + ": is a folder; name a file in it");
  if (!fs::is_directory(dir, ec)) throw OptionError(named + ": the folder " + dir.string() + " does not exist");
  for (const auto& input : inputs_)
    if (fs::exists(destination, ec) && fs::exists(input, ec) && fs::equivalent(destination, input, ec))
      throw OptionError(named + ": is the input " + input.string() + "; writing it would destroy the input");
  for (const auto& t : targets_)
    if (t.destination.lexically_normal() == destination.lexically_normal() ||
        (fs::exists(destination, ec) && fs::exists(t.destination, ec) && fs::equivalent(destination, t.destination, ec)))
      throw OptionError(named + ": is named twice as an output");

  // One staging folder per destination folder: renames into place stay on one file system.
  fs::path folder;
  for (const auto& f : folders_)
    if (fs::equivalent(folder_of(f), dir, ec)) folder = f;
  if (folder.empty()) {
    remove_stale_temporaries(dir);
    std::string pattern = (dir / (temporary_prefix() + "stage.XXXXXX")).string();
    if (::mkdtemp(pattern.data()) == nullptr)
      throw Error(named + ": cannot write in " + dir.string() + ": " + std::strerror(errno));
    folder = pattern;
    folders_.push_back(folder);
    register_folder(folder);
  }
  const fs::path staged = folder / destination.filename();
  targets_.push_back({destination, staged, target});
  return staged;
}

void OutputSet::commit() {
  for (const auto& t : targets_) {
    std::error_code ec;
    if (!fs::exists(t.staged, ec)) throw Error(t.destination.string() + ": was not written");
  }
  // Side files first (a .gltf's .bin), so that no main file ever refers to one not there yet.
  for (const auto& folder : folders_) {
    std::vector<fs::path> side;
    for (const auto& entry : fs::directory_iterator(folder)) {
      const std::string name = entry.path().filename().string();
      const bool main = std::any_of(targets_.begin(), targets_.end(), [&](const Target& t) { return t.staged == entry.path(); });
      if (!main && name.rfind(".treeskel-", 0) != 0) side.push_back(entry.path());
    }
    for (const auto& f : side) fs::rename(f, folder_of(folder) / f.filename());
  }
  for (const auto& t : targets_) fs::rename(t.staged, t.destination);
}

std::string OutputSet::explain(std::string message) const {
  auto replace_all = [&](const std::string& from, const std::string& to) {
    for (std::size_t at = message.find(from); at != std::string::npos; at = message.find(from, at + to.size()))
      message.replace(at, from.size(), to);
  };
  for (const auto& t : targets_) replace_all(t.staged.string(), t.named.string());
  for (const auto& f : folders_) replace_all(f.string(), folder_of(f).string());  // side files: their folder
  return message;
}

}  // namespace treeskel::io
