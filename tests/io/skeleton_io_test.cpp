#include "treeskel/io/skeleton_io.h"

#include "support/synthetic.h"
#include "treeskel/error.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>

namespace treeskel {
namespace {

Skeleton sample() {
  Skeleton s;
  s.offset = {312000.0, 5012000.0, 100.0};
  const Eigen::Vector3d at[] = {{0, 0, 0}, {0, 0, 1.25}, {-0.5, 0, 2}, {0.5, 0.125, 2}};
  for (int i = 0; i < 4; ++i) {
    SkeletonNode n;
    n.position = at[i];
    n.radius = 0.1 / (i + 1);
    n.points = {std::uint32_t(i)};
    add_node(s, n);
  }
  boost::add_edge(0, 1, s.graph);
  boost::add_edge(1, 2, s.graph);
  boost::add_edge(1, 3, s.graph);
  s.root = 0;
  return s;
}

void expect_same(const Skeleton& a, const Skeleton& b) {
  ASSERT_EQ(a.node_count(), b.node_count());
  ASSERT_EQ(a.edge_count(), b.edge_count());
  EXPECT_EQ(a.root, b.root);
  for (NodeId v = 0; v < a.node_count(); ++v) {
    EXPECT_EQ(a[v].position + a.offset, b[v].position + b.offset);
    EXPECT_EQ(a[v].radius, b[v].radius);
  }
  EXPECT_TRUE(is_tree(b.graph));
}

TEST(SkeletonIo, PlyAndJsonRoundTripExactlyInTheInputFrame) {
  const test::TempDir dir;
  for (const char* name : {"s.ply", "s.json"}) {
    io::write_skeleton(dir.path(name), sample());
    expect_same(sample(), io::read_skeleton(dir.path(name)));
  }
}

TEST(SkeletonIo, PlyHasTheLayoutMeshLabReads) {
  const test::TempDir dir;
  io::write_skeleton(dir.path("s.ply"), sample());
  std::ifstream in(dir.path("s.ply"));
  std::stringstream text;
  text << in.rdbuf();
  const std::string t = text.str();
  EXPECT_NE(t.find("element vertex 4\nproperty double x\nproperty double y\nproperty double z\nproperty double radius\n"), std::string::npos);
  EXPECT_NE(t.find("element edge 3\nproperty int vertex1\nproperty int vertex2\nend_header\n"), std::string::npos);
  EXPECT_NE(t.find("312000 5012000 101.25 0.05\n"), std::string::npos);
}

TEST(SkeletonIo, ObjPolylines) {
  const test::TempDir dir;
  io::write_skeleton(dir.path("s.obj"), sample());
  std::ifstream in(dir.path("s.obj"));
  std::string line;
  int v = 0, l = 0;
  while (std::getline(in, line)) {
    v += line.rfind("v ", 0) == 0;
    l += line.rfind("l ", 0) == 0;
  }
  EXPECT_EQ(v, 4);
  EXPECT_EQ(l, 3);
}

TEST(SkeletonIo, JsonListsCountsAndRoot) {
  const auto j = nlohmann::json::parse(io::skeleton_to_json(sample()));
  EXPECT_EQ(j["root"], 0);
  EXPECT_EQ(j["branch_points"], 1);
  EXPECT_EQ(j["endpoints"], 3);
  EXPECT_EQ(j["nodes"].size(), 4u);
  EXPECT_EQ(j["nodes"][3]["position"][1], 5012000.125);
}

TEST(SkeletonIo, BadFilesAndExtensions) {
  const test::TempDir dir;
  EXPECT_THROW(io::write_skeleton(dir.path("s.stl"), sample()), Error);
  EXPECT_FALSE(std::filesystem::exists(dir.path("s.stl")));
  std::ofstream(dir.path("bad.json")) << "{\"nodes\": [{\"position\": [0,0,0]}], \"edges\": [[0, 5]]}";
  EXPECT_THROW(io::read_skeleton(dir.path("bad.json")), InputError);
  std::ofstream(dir.path("broken.json")) << "{\"nodes\": [";
  EXPECT_THROW(io::read_skeleton(dir.path("broken.json")), InputError);
}

}  // namespace
}  // namespace treeskel
