#include "treeskel/io/skeleton_io.h"

#include "support/synthetic.h"
#include "treeskel/error.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstring>
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
  // A number too large for any type (found by the fuzzer; nlohmann throws out_of_range, not parse_error).
  std::ofstream(dir.path("huge.json")) << "{\"nodes\": [{\"position\": [1" << std::string(400, '0') << "e99999, 0, 0]}]}";
  EXPECT_THROW(io::read_skeleton(dir.path("huge.json")), InputError);
  std::ofstream(dir.path("huge_int.json")) << "{\"nodes\": [], \"edges\": [], \"root\": 3" << std::string(400, '3') << "}";
  EXPECT_THROW(io::read_skeleton(dir.path("huge_int.json")), InputError);
  // Indices that are fractions, negative or not numbers (found by the fuzzer: nlohmann's conversion of
  // -5.3 to size_t is undefined behaviour).
  for (const char* index : {"-5.3", "0.5", "-1", "\"0\"", "true", "1e3"}) {
    std::ofstream(dir.path("index.json")) << "{\"nodes\": [{\"position\": [0,0,0]}, {\"position\": [0,0,1]}], \"edges\": [[0, "
                                          << index << "]]}";
    EXPECT_THROW(io::read_skeleton(dir.path("index.json")), InputError) << index;
    std::ofstream(dir.path("root.json")) << "{\"nodes\": [{\"position\": [0,0,0]}], \"edges\": [], \"root\": " << index << "}";
    EXPECT_THROW(io::read_skeleton(dir.path("root.json")), InputError) << index;
  }
}

// Skeleton PLY files are read by the same PLY reader as clouds: binary too, any property order, the
// root from its comment.
TEST(SkeletonIo, BinaryPlyWithOtherPropertiesIsRead) {
  const test::TempDir dir;
  std::string ply = "ply\nformat binary_big_endian 1.0\ncomment root 1\nelement vertex 3\nproperty float radius\n"
                    "property uchar red\nproperty double x\nproperty double y\nproperty double z\nelement edge 2\n"
                    "property uint vertex2\nproperty uint vertex1\nend_header\n";
  const auto put = [&](auto v) {
    char b[sizeof v];
    std::memcpy(b, &v, sizeof v);
    std::reverse(b, b + sizeof v);  // big-endian on a little-endian host
    ply.append(b, sizeof v);
  };
  const double at[3][3] = {{0, 0, 5}, {0, 0, 0}, {1, 0, 6}};
  for (int i = 0; i < 3; ++i) {
    put(float(0.5f / (i + 1)));
    put(std::uint8_t(7));
    for (double c : at[i]) put(c);
  }
  put(std::uint32_t(0)), put(std::uint32_t(1));
  put(std::uint32_t(2)), put(std::uint32_t(0));
  std::ofstream(dir.path("b.ply"), std::ios::binary) << ply;
  const Skeleton s = io::read_skeleton(dir.path("b.ply"));
  ASSERT_EQ(s.node_count(), 3u);
  EXPECT_EQ(s.edge_count(), 2u);
  EXPECT_EQ(s.root, 1u);
  EXPECT_EQ(s[2].position, Eigen::Vector3d(1, 0, 6));
  EXPECT_EQ(s[1].radius, 0.25);
  EXPECT_TRUE(is_tree(s.graph));
  EXPECT_TRUE(io::looks_like_skeleton(dir.path("b.ply")));
}

TEST(SkeletonIo, LooksLikeSkeletonTellsCloudsAndMeshesApart) {
  const test::TempDir dir;
  io::write_skeleton(dir.path("s.ply"), sample());
  io::write_skeleton(dir.path("s.json"), sample());
  EXPECT_TRUE(io::looks_like_skeleton(dir.path("s.ply")));
  EXPECT_TRUE(io::looks_like_skeleton(dir.path("s.json")));
  // A cloud that carries a few edges (a scanner's or an editor's extra element) is a cloud.
  std::string cloud = "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\nproperty float z\n"
                      "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n";
  for (int i = 0; i < 6; ++i) cloud += std::to_string(i) + " 0 0\n";
  std::ofstream(dir.path("cloud.ply")) << cloud + "0 1\n";
  EXPECT_FALSE(io::looks_like_skeleton(dir.path("cloud.ply")));
  // A mesh with edges is a mesh, and a cloud without edges a cloud.
  std::string mesh = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                     "element face 1\nproperty list uchar int vertex_indices\nelement edge 3\nproperty int vertex1\n"
                     "property int vertex2\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n0 1\n1 2\n2 0\n";
  std::ofstream(dir.path("mesh.ply")) << mesh;
  EXPECT_FALSE(io::looks_like_skeleton(dir.path("mesh.ply")));
  std::ofstream(dir.path("plain.ply")) << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                           "property float y\nproperty float z\nend_header\n0 0 0\n";
  EXPECT_FALSE(io::looks_like_skeleton(dir.path("plain.ply")));
  EXPECT_FALSE(io::looks_like_skeleton(dir.path("cloud.xyz")));
}

TEST(SkeletonIo, EdgesNamingMissingVerticesAreRefused) {
  const test::TempDir dir;
  for (const char* edge : {"0 3", "0 -1", "0 1.5", "0 1e300", "0 nan"}) {
    std::ofstream(dir.path("e.ply")) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                        "property float z\nelement edge 1\nproperty int vertex1\nproperty int vertex2\n"
                                        "end_header\n0 0 0\n0 0 1\n0 0 2\n"
                                     << edge << "\n";
    EXPECT_THROW(io::read_skeleton(dir.path("e.ply")), InputError) << edge;
  }
}

}  // namespace
}  // namespace treeskel
