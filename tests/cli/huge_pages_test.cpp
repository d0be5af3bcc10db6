// The tool restarts itself once with glibc's huge-page and memory-reuse tunables, and gives the
// programs it runs the user's environment back (cli/huge_pages.h).
#include "huge_pages.h"
#include "run_tool.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

namespace {

std::string probe(const std::string& environment, const std::string& arguments = "") {
  return treeskel::test::capture("env -u GLIBC_TUNABLES -u TREESKEL_NO_HUGE_PAGES " + environment + " '" HUGE_PAGES_PROBE "' " + arguments).out;
}

using treeskel::cli::Memory;

Memory memory_for(std::vector<const char*> argv) {
  argv.insert(argv.begin(), "treeskel");
  return treeskel::cli::memory_for(static_cast<int>(argv.size()), argv.data());
}

bool glibc_allocator() {
#if defined(__SANITIZE_ADDRESS__)
  return false;  // AddressSanitizer's allocator takes the place of glibc's: no tunable applies
#endif
  return true;
}

bool huge_pages_possible() {
  if (!glibc_allocator()) return false;
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

TEST(HugePages, AModelReusesMemoryWithoutHugePages) {
  EXPECT_EQ(memory_for({"model", "tree.xyz", "-o", "tree.glb"}), Memory::reuse_only);
  EXPECT_EQ(memory_for({"--threads", "2", "model", "tree.xyz"}), Memory::reuse_only);
  EXPECT_EQ(memory_for({"--threads", "1", "skeletonize", "model", "-o", "s.ply"}), Memory::huge_pages);  // a cloud named model
  EXPECT_EQ(memory_for({"skeletonize", "tree.xyz"}), Memory::huge_pages);
  EXPECT_EQ(memory_for({"plot", "plot.laz", "-o", "trees"}), Memory::huge_pages);  // its models run as processes of their own
  EXPECT_EQ(memory_for({"--help"}), Memory::huge_pages);
  EXPECT_EQ(memory_for({}), Memory::huge_pages);
}

TEST(HugePages, TunablesKeepTheUsersAndAskForHugePagesOnlyWhereWanted) {
  const std::string reuse = "glibc.malloc.mmap_threshold=33554432:glibc.malloc.trim_threshold=1073741824";
  EXPECT_EQ(treeskel::cli::tunables_for("", Memory::huge_pages, true), "glibc.malloc.hugetlb=1:" + reuse);
  EXPECT_EQ(treeskel::cli::tunables_for("", Memory::reuse_only, true), reuse);
  EXPECT_EQ(treeskel::cli::tunables_for("", Memory::reuse_only, false), reuse);  // no huge page asked for
  EXPECT_EQ(treeskel::cli::tunables_for("", Memory::huge_pages, false), std::nullopt);
  EXPECT_EQ(treeskel::cli::tunables_for("glibc.malloc.hugetlb=0", Memory::reuse_only, true), std::nullopt);
  EXPECT_EQ(treeskel::cli::tunables_for("glibc.malloc.tcache_count=5", Memory::reuse_only, true), "glibc.malloc.tcache_count=5:" + reuse);
  EXPECT_EQ(treeskel::cli::tunables_for("glibc.malloc.mmap_threshold=65536", Memory::huge_pages, true),
            "glibc.malloc.mmap_threshold=65536:glibc.malloc.hugetlb=1:glibc.malloc.trim_threshold=1073741824");
}

TEST(HugePages, AModelRestartsWithTheReuseTunables) {
  if (!glibc_allocator()) GTEST_SKIP() << "glibc's allocator is not in use";
  // Restarted (the 32 MB threshold holds the block in the heap), the environment put back.
  EXPECT_EQ(probe("", "model"), "now: (unset)\nmarker: unset\n20 MB from: heap\n");
  EXPECT_EQ(probe("TREESKEL_NO_HUGE_PAGES=1", "model"), "now: (unset)\nmarker: unset\n20 MB from: a mapping\n");
}
