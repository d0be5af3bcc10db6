#include "treeskel/io/atomic_file.h"

#include "support/synthetic.h"
#include "treeskel/error.h"
#include "treeskel/io/point_cloud_io.h"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

namespace treeskel {
namespace {

namespace fs = std::filesystem;

std::string content(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(AtomicFile, FailureLeavesTheOldFileAndNoTemporary) {
  const test::TempDir dir;
  const std::string target = dir.path("out.txt");
  io::write_atomically(target, [](std::ostream& out) { out << "first"; });
  EXPECT_EQ(content(target), "first");
  EXPECT_THROW(io::write_atomically(target,
                                    [](std::ostream& out) {
                                      out << "half";
                                      throw Error("stopped");
                                    }),
               Error);
  EXPECT_EQ(content(target), "first");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.root()), fs::directory_iterator()), 1);
}

TEST(AtomicFile, MissingFolderIsAnErrorAndCreatesNothing) {
  const test::TempDir dir;
  EXPECT_THROW(io::write_atomically(dir.path("no/such/folder/out.txt"), [](std::ostream& out) { out << "x"; }), Error);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.root()), fs::directory_iterator()), 0);
}

TEST(AtomicFile, UnknownExtensionWritesNothing) {
  const test::TempDir dir;
  PointCloud c;
  c.positions = {{0, 0, 0}};
  EXPECT_THROW(io::write_point_cloud(dir.path("cloud.e57"), c), Error);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.root()), fs::directory_iterator()), 0);
}

TEST(AtomicFile, StaleTemporariesOfGoneAndZombieProcessesAreRemovedOthersKept) {
  const test::TempDir dir;
  // The prefix a temporary of process `pid` would have on this machine.
  const std::string ours = io::temporary_prefix();
  const std::string machine = ours.substr(0, ours.size() - std::to_string(::getpid()).size() - 1);
  auto temporary = [&](pid_t pid) {
    const std::string path = dir.path(machine + std::to_string(pid) + "-0-tree.glb");
    std::ofstream(path) << "half written\n";
    return path;
  };
  // A child that has ended but is not reaped yet: a zombie, as a killed run's process is until its
  // parent or init reaps it.
  const pid_t zombie = ::fork();
  if (zombie == 0) _exit(0);
  ASSERT_GT(zombie, 0);
  const pid_t alive = ::fork();
  if (alive == 0) {
    ::pause();
    _exit(0);
  }
  ASSERT_GT(alive, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the first child has ended by now
  const std::string of_zombie = temporary(zombie), of_alive = temporary(alive), of_ours = temporary(::getpid());
  const std::string other = dir.path(".treeskel-elsewhere-1-0-tree.glb");
  std::ofstream(other) << "another machine's\n";
  EXPECT_EQ(io::remove_stale_temporaries(dir.root()), 1u);
  EXPECT_FALSE(fs::exists(of_zombie));
  EXPECT_TRUE(fs::exists(of_alive));
  EXPECT_TRUE(fs::exists(of_ours));
  EXPECT_TRUE(fs::exists(other));
  ::kill(alive, SIGKILL);
  ::waitpid(alive, nullptr, 0);
  ::waitpid(zombie, nullptr, 0);
  // Gone altogether.
  EXPECT_EQ(io::remove_stale_temporaries(dir.root()), 1u);
  EXPECT_FALSE(fs::exists(of_alive));
  EXPECT_TRUE(fs::exists(of_ours));
}

TEST(AtomicFile, ExtensionIsLowerCase) {
  EXPECT_EQ(io::extension_of("a/b/Cloud.PLY"), "ply");
  EXPECT_EQ(io::extension_of("noext"), "");
}

}  // namespace
}  // namespace treeskel
