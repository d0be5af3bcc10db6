#include "huge_pages.h"

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

#include <unistd.h>

namespace treeskel::cli {

namespace {

// Set in the restarted process: what GLIBC_TUNABLES held before ("-" when it was unset).
constexpr const char* kBefore = "TREESKEL_GLIBC_TUNABLES_BEFORE";

void set_or_unset(const char* name, const std::string& value, bool set) {
  if (set) ::setenv(name, value.c_str(), 1);
  else ::unsetenv(name);
}

bool kernel_huge_pages_on() {
  std::ifstream mode("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  return std::getline(mode, modes) && modes.find("[never]") == std::string::npos;
}

}  // namespace

Memory memory_for(int argc, const char* const* argv) {
  for (int i = 1; i < argc; ++i) {
    const char* a = argv[i];
    if (std::strcmp(a, "--threads") == 0) {
      ++i;  // its value
      continue;
    }
    if (a[0] == '-') continue;
    return std::strcmp(a, "model") == 0 ? Memory::reuse_only : Memory::huge_pages;
  }
  return Memory::huge_pages;
}

std::optional<std::string> tunables_for(const std::string& user, Memory memory, bool huge_pages_on) {
  if (user.find("glibc.malloc.hugetlb") != std::string::npos) return std::nullopt;
  if (memory == Memory::huge_pages && !huge_pages_on) return std::nullopt;
  std::string value = user;
  auto add = [&](const std::string& tunable) {
    if (user.find(tunable.substr(0, tunable.find('='))) == std::string::npos) value += (value.empty() ? "" : ":") + tunable;
  };
  if (memory == Memory::huge_pages) add("glibc.malloc.hugetlb=1");
  add("glibc.malloc.mmap_threshold=33554432");
  add("glibc.malloc.trim_threshold=1073741824");
  return value;
}

void restart_with_huge_pages(char** argv, Memory memory) {
#if defined(__linux__) && defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 35))
  if (const char* before = std::getenv(kBefore)) {
    // The restarted process: the programs it runs (Chromium for a preview, the processes of a
    // batch) get the environment the user gave, not these tunables.
    const std::string was = before;
    set_or_unset("GLIBC_TUNABLES", was, was != "-");
    ::unsetenv(kBefore);
    return;
  }
  if (std::getenv("TREESKEL_NO_HUGE_PAGES")) return;
  const char* set = std::getenv("GLIBC_TUNABLES");
  const std::string tunables = set ? set : "";
  const auto value = tunables_for(tunables, memory, kernel_huge_pages_on());
  if (!value) return;
  if (::setenv("GLIBC_TUNABLES", value->c_str(), 1) != 0 || ::setenv(kBefore, set ? set : "-", 1) != 0) return;
  ::execv("/proc/self/exe", argv);
  // The restart failed: on as we are, with the environment as it was.
  set_or_unset("GLIBC_TUNABLES", tunables, set != nullptr);
  ::unsetenv(kBefore);
#else
  (void)argv;
  (void)memory;
#endif
}

}  // namespace treeskel::cli
