#include "huge_pages.h"

#include <cstdlib>
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

}  // namespace

void restart_with_huge_pages(char** argv) {
#if defined(__linux__) && defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 35))
  if (const char* before = std::getenv(kBefore)) {
    // The restarted process: the programs it runs (Chromium for a preview, the processes of a
    // batch) get the environment the user gave, not these tunables.
    const std::string was = before;
    set_or_unset("GLIBC_TUNABLES", was, was != "-");
    ::unsetenv(kBefore);
    return;
  }
  const char* set = std::getenv("GLIBC_TUNABLES");
  const std::string tunables = set ? set : "";
  if (tunables.find("glibc.malloc.hugetlb") != std::string::npos || std::getenv("TREESKEL_NO_HUGE_PAGES")) return;
  std::ifstream mode("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  if (!std::getline(mode, modes) || modes.find("[never]") != std::string::npos) return;
  std::string value = tunables;
  for (const std::string tunable : {"glibc.malloc.hugetlb=1", "glibc.malloc.mmap_threshold=33554432",
                                    "glibc.malloc.trim_threshold=1073741824"})
    if (tunables.find(tunable.substr(0, tunable.find('='))) == std::string::npos)
      value += (value.empty() ? "" : ":") + tunable;
  if (::setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0 || ::setenv(kBefore, set ? set : "-", 1) != 0) return;
  ::execv("/proc/self/exe", argv);
  // The restart failed: on as we are, with the environment as it was.
  set_or_unset("GLIBC_TUNABLES", tunables, set != nullptr);
  ::unsetenv(kBefore);
#else
  (void)argv;
#endif
}

}  // namespace treeskel::cli
