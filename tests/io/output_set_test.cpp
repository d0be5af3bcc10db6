#include "treeskel/io/output_set.h"

#include "support/synthetic.h"
#include "treeskel/error.h"
#include "treeskel/io/atomic_file.h"

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace treeskel {
namespace {

namespace fs = std::filesystem;

std::string content(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void put(const fs::path& path, const std::string& text) {
  io::write_atomically(path, [&](std::ostream& out) { out << text; });
}

std::size_t entries(const fs::path& dir) {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

TEST(OutputSet, CommitMovesEveryFileWithItsSideFiles) {
  const test::TempDir dir;
  put(dir.path("b.json"), "old");
  {
    io::OutputSet set;
    const fs::path a = set.stage(dir.path("a.gltf"));
    const fs::path b = set.stage(dir.path("b.json"));
    put(a, "main");
    put(a.parent_path() / "a.bin", "side");  // as the glTF writer puts its buffer beside the file
    put(b, "new");
    EXPECT_EQ(content(dir.path("b.json")), "old");  // nothing moves before the commit
    EXPECT_FALSE(fs::exists(dir.path("a.gltf")));
    set.commit();
  }
  EXPECT_EQ(content(dir.path("a.gltf")), "main");
  EXPECT_EQ(content(dir.path("a.bin")), "side");
  EXPECT_EQ(content(dir.path("b.json")), "new");
  EXPECT_EQ(entries(dir.root()), 3u);  // the staging folder is gone
}

TEST(OutputSet, WithoutCommitNothingIsLeft) {
  const test::TempDir dir;
  put(dir.path("b.json"), "old");
  {
    io::OutputSet set;
    put(set.stage(dir.path("a.obj")), "half");
    put(set.stage(dir.path("b.json")), "new");
    // an error here: the set goes out of scope uncommitted
  }
  EXPECT_EQ(content(dir.path("b.json")), "old");
  EXPECT_EQ(entries(dir.root()), 1u);
}

TEST(OutputSet, CommitRefusesWhenAFileWasNotWritten) {
  const test::TempDir dir;
  io::OutputSet set;
  put(set.stage(dir.path("a.obj")), "x");
  set.stage(dir.path("b.obj"));
  EXPECT_THROW(set.commit(), Error);
  EXPECT_FALSE(fs::exists(dir.path("a.obj")));
}

TEST(OutputSet, TargetsAreCheckedWhenStaged) {
  const test::TempDir dir;
  put(dir.path("in.ply"), "cloud");
  fs::create_symlink(dir.path("in.ply"), dir.path("alias.ply"));
  fs::create_directory(dir.path("folder"));
  io::OutputSet set({dir.path("in.ply")});
  EXPECT_THROW(set.stage(dir.path("in.ply")), OptionError);
  EXPECT_THROW(set.stage(dir.path("alias.ply")), OptionError);
  EXPECT_THROW(set.stage(dir.path("folder")), OptionError);
  EXPECT_THROW(set.stage(dir.path("no/such/out.ply")), OptionError);
  set.stage(dir.path("out.ply"));
  EXPECT_THROW(set.stage(dir.path("./out.ply")), OptionError);  // named twice
  EXPECT_EQ(content(dir.path("in.ply")), "cloud");
}

TEST(OutputSet, ExplainNamesTheTargetNotTheStagedFile) {
  const test::TempDir dir;
  io::OutputSet set;
  const fs::path staged = set.stage(dir.path("m.ply"));
  EXPECT_EQ(set.explain(staged.string() + ": writing failed"), dir.path("m.ply") + ": writing failed");
  EXPECT_EQ(set.explain((staged.parent_path() / "m.bin").string()), (fs::path(dir.root()) / "m.bin").string());
}

/// Runs `body` in a forked child (which stages outputs and is then killed by a signal) and returns
/// the child's wait status.
template <class Body>
int status_of_child(Body body) {
  const pid_t child = ::fork();
  if (child == 0) {
    body();
    ::_exit(0);
  }
  int status = 0;
  if (child > 0) ::waitpid(child, &status, 0);
  return status;
}

// SIGTERM (and SIGINT, SIGHUP) while outputs are staged leaves none of them, and still ends the process
// by the signal.
TEST(OutputSet, TerminationLeavesNothing) {
  const test::TempDir dir;
  const int status = status_of_child([&] {
    io::OutputSet set;
    put(set.stage(dir.path("a.glb")), "staged");
    put(set.stage(dir.path("b.json")), "staged");
    ::raise(SIGTERM);
  });
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM);
  EXPECT_EQ(entries(dir.root()), 0u);
}

// A run killed outright (SIGKILL) leaves its staging folder; the next run in that folder removes it.
TEST(OutputSet, RunsKilledOutrightAreCleanedUpLater) {
  const test::TempDir dir;
  const int status = status_of_child([&] {
    io::OutputSet set;
    put(set.stage(dir.path("a.glb")), "staged");
    ::raise(SIGKILL);
  });
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
  ASSERT_EQ(entries(dir.root()), 1u);  // the dead run's staging folder
  fs::create_directory(dir.path(".treeskel-someone-else"));  // not ours: kept
  put(dir.path("b.json"), "x");
  EXPECT_EQ(entries(dir.root()), 2u);
  EXPECT_TRUE(fs::exists(dir.path(".treeskel-someone-else")));
}

}  // namespace
}  // namespace treeskel
