#include "treeskel/io/atomic_file.h"

#include "treeskel/error.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <functional>

namespace treeskel::io {

namespace fs = std::filesystem;

namespace {

/// A short tag of this machine, so that runs on other machines sharing a folder are told apart.
std::string machine_tag() {
  char name[256] = {};
  ::gethostname(name, sizeof name - 1);
  const std::size_t h = std::hash<std::string>{}(name);
  char out[9];
  std::snprintf(out, sizeof out, "%08x", static_cast<unsigned>(h & 0xffffffffu));
  return out;
}

/// Flushes a written file to the device and reports whether the device took it.
bool synced(const fs::path& file) {
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool ok = ::fsync(fd) == 0 || errno == EINVAL;  // EINVAL: a file system without fsync
  return ::close(fd) == 0 && ok;
}

/// Whether process `pid` is gone: it does not exist, or it is a zombie (killed or ended, and not yet
/// reaped by its parent or by init, which can take a second; it will never write again).
bool process_gone(pid_t pid) {
  if (::kill(pid, 0) != 0) return errno == ESRCH;
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text;
  std::getline(stat, text);
  const std::size_t close = text.rfind(')');  // the name, in parentheses, may hold spaces
  return close != std::string::npos && close + 2 < text.size() && (text[close + 2] == 'Z' || text[close + 2] == 'X');
}

/// Why the last system call failed, or a generic reason when it did not say.
std::string reason() { return errno != 0 ? std::string(std::strerror(errno)) : std::string("the disk refused the data"); }

}  // namespace

std::string extension_of(const fs::path& path) {
  std::string ext = path.extension().string();
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

std::string read_whole_file(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path.string() + ": no such file");
  if (fs::is_directory(path, ec)) throw InputError(path.string() + ": is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot open for reading: " + std::strerror(errno));
  std::string data(std::istreambuf_iterator<char>(in), {});
  if (in.bad()) throw InputError(path.string() + ": read failed: " + std::strerror(errno));
  return data;
}

std::string temporary_prefix() {
  static const std::string machine = ".treeskel-" + machine_tag() + "-";
  return machine + std::to_string(::getpid()) + "-";  // not cached: a forked child has its own
}

std::size_t remove_stale_temporaries(const fs::path& dir) {
  static const std::string ours = ".treeskel-" + machine_tag() + "-";
  std::size_t removed = 0;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.rfind(ours, 0) != 0) continue;
    const std::string rest = name.substr(ours.size());
    const std::size_t dash = rest.find('-');
    if (dash == 0 || dash == std::string::npos || !std::all_of(rest.begin(), rest.begin() + dash, ::isdigit)) continue;
    const long pid = std::strtol(rest.substr(0, dash).c_str(), nullptr, 10);
    if (pid <= 0 || pid == ::getpid() || !process_gone(static_cast<pid_t>(pid))) continue;
    std::error_code gone;
    if (fs::remove_all(it->path(), gone) > 0 && !gone) ++removed;
  }
  return removed;
}

fs::path folder_of(const fs::path& path) { return path.has_parent_path() ? path.parent_path() : fs::path("."); }

fs::path write_destination(const fs::path& target) {
  std::error_code ec;
  if (!fs::is_symlink(target, ec)) return target;
  fs::path to = fs::read_symlink(target, ec);
  if (ec) return target;
  if (to.is_relative()) to = folder_of(target) / to;
  return write_destination(to.lexically_normal());
}

void write_atomically(const fs::path& requested, const std::function<void(std::ostream&)>& body) {
  static std::atomic<unsigned> counter{0};
  const fs::path target = write_destination(requested);
  const fs::path dir = folder_of(target);
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw Error(requested.string() + ": cannot write: folder " + dir.string() + " does not exist");
  if (fs::is_directory(target, ec)) throw Error(requested.string() + ": cannot write: it is a directory");
  remove_stale_temporaries(dir);
  const fs::path temp = dir / (temporary_prefix() + std::to_string(counter++) + "-" + target.filename().string());
  try {
    errno = 0;
    {
      std::ofstream out(temp, std::ios::binary | std::ios::trunc);
      if (!out) throw Error(requested.string() + ": cannot write: " + std::strerror(errno));
      body(out);
      out.close();
      if (out.fail()) throw Error(requested.string() + ": writing failed: " + reason() + " (disk full?)");
    }
    if (!synced(temp)) throw Error(requested.string() + ": writing failed: " + reason() + " (disk full?)");
    fs::rename(temp, target);
  } catch (...) {
    fs::remove(temp, ec);
    throw;
  }
}

}  // namespace treeskel::io
