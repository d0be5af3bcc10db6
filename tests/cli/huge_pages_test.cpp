// The tool restarts itself once with glibc's huge-page and memory-reuse tunables, and gives the
// programs it runs the user's environment back (cli/huge_pages.h).
#include "run_tool.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

namespace {

std::string probe(const std::string& environment) {
  return treeskel::test::capture("env -u GLIBC_TUNABLES -u TREESKEL_NO_HUGE_PAGES " + environment + " '" HUGE_PAGES_PROBE "'").out;
}

bool huge_pages_possible() {
#if defined(__SANITIZE_ADDRESS__)
  return false;  // AddressSanitizer's allocator takes the place of glibc's: no tunable applies
#endif
  std::ifstream mode("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  return std::getline(mode, modes) && modes.find("[never]") == std::string::npos;
}

}  // namespace

TEST(HugePages, RestartsWithTheTunablesAndPutsTheEnvironmentBack) {
  if (!huge_pages_possible()) GTEST_SKIP() << "glibc's allocator is not in use, or transparent huge pages are off";
  EXPECT_EQ(probe(""), "now: (unset)\nmarker: unset\n20 MB from: heap\n");
}

TEST(HugePages, KeepsTheUsersTunables) {
  if (!huge_pages_possible()) GTEST_SKIP() << "glibc's allocator is not in use, or transparent huge pages are off";
  EXPECT_EQ(probe("GLIBC_TUNABLES=glibc.malloc.tcache_count=5"),
            "now: glibc.malloc.tcache_count=5\nmarker: unset\n"
            "20 MB from: heap\n");
  // A value the user chose for one of ours stays (a 64 kB threshold: the block gets a mapping).
  EXPECT_EQ(probe("GLIBC_TUNABLES=glibc.malloc.mmap_threshold=65536"),
            "now: glibc.malloc.mmap_threshold=65536\nmarker: unset\n20 MB from: a mapping\n");
}

TEST(HugePages, DoesNothingWhenTheUserSaysSo) {
  if (!huge_pages_possible()) GTEST_SKIP() << "glibc's allocator is not in use, or transparent huge pages are off";
  EXPECT_EQ(probe("GLIBC_TUNABLES=glibc.malloc.hugetlb=0"),
            "now: glibc.malloc.hugetlb=0\nmarker: unset\n20 MB from: a mapping\n");
  EXPECT_EQ(probe("TREESKEL_NO_HUGE_PAGES=1"), "now: (unset)\nmarker: unset\n20 MB from: a mapping\n");
}
