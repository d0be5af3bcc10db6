#include "treeskel/io/atomic_file.h"

#include "support/synthetic.h"
#include "treeskel/error.h"
#include "treeskel/io/point_cloud_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

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

TEST(AtomicFile, ExtensionIsLowerCase) {
  EXPECT_EQ(io::extension_of("a/b/Cloud.PLY"), "ply");
  EXPECT_EQ(io::extension_of("noext"), "");
}

}  // namespace
}  // namespace treeskel
