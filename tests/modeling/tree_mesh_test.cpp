#include "treeskel/modeling/tree_mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace treeskel::modeling {
namespace {

using P = TreeMesh::Point;

/// A tetrahedron with corners o, o+x, o+y, o+z, faces outward (or inward when flipped).
void add_tetrahedron(TreeMesh& m, const P& o, bool flipped = false) {
  const auto a = m.add_vertex(o), b = m.add_vertex(o + P(1, 0, 0)), c = m.add_vertex(o + P(0, 1, 0)),
             d = m.add_vertex(o + P(0, 0, 1));
  auto face = [&](TreeMesh::VertexHandle x, TreeMesh::VertexHandle y, TreeMesh::VertexHandle z) {
    if (flipped) m.add_face(x, z, y);
    else m.add_face(x, y, z);
  };
  face(a, c, b);
  face(a, b, d);
  face(a, d, c);
  face(b, c, d);
}

TEST(CheckMesh, ClosedOutwardTetrahedron) {
  TreeMesh m;
  add_tetrahedron(m, P(0, 0, 0));
  const MeshCheck c = check_mesh(m);
  EXPECT_TRUE(c.ok()) << c.problem();
  EXPECT_EQ(c.boundary_edges, 0u);
  EXPECT_EQ(c.components, 1u);
  EXPECT_EQ(c.self_intersections, 0u);
  EXPECT_NEAR(c.volume, 1.0 / 6.0, 1e-12);
}

TEST(CheckMesh, FindsAHole) {
  TreeMesh m;
  add_tetrahedron(m, P(0, 0, 0));
  m.request_face_status();
  m.request_edge_status();
  m.request_vertex_status();
  m.delete_face(*m.faces_begin(), false);
  m.garbage_collection();
  const MeshCheck c = check_mesh(m);
  EXPECT_EQ(c.boundary_edges, 3u);
  EXPECT_FALSE(c.ok());
  EXPECT_NE(c.problem().find("not closed"), std::string::npos);
}

TEST(CheckMesh, FindsInwardNormalsAndSeveralComponents) {
  TreeMesh inward;
  add_tetrahedron(inward, P(0, 0, 0), true);
  EXPECT_LT(check_mesh(inward).volume, 0.0);
  EXPECT_NE(check_mesh(inward).problem().find("inward"), std::string::npos);

  TreeMesh two;
  add_tetrahedron(two, P(0, 0, 0));
  add_tetrahedron(two, P(5, 0, 0));
  EXPECT_EQ(check_mesh(two).components, 2u);
  EXPECT_FALSE(check_mesh(two).ok());
}

TEST(CheckMesh, FindsSelfIntersections) {
  TreeMesh m;
  add_tetrahedron(m, P(0, 0, 0));
  add_tetrahedron(m, P(0.2, 0.2, 0.2));
  EXPECT_GT(check_mesh(m).self_intersections, 0u);
  EXPECT_EQ(check_mesh(m, false).self_intersections, 0u);  // not asked
}

// Testing a subset of the faces finds the crossings between two of them and no others.
TEST(CheckMesh, SelfIntersectionsAmongSomeFaces) {
  TreeMesh m;
  add_tetrahedron(m, P(0, 0, 0));
  add_tetrahedron(m, P(0.2, 0.2, 0.2));
  add_tetrahedron(m, P(5, 0, 0));
  const auto all = self_intersecting_faces(m);
  ASSERT_FALSE(all.empty());
  std::vector<std::size_t> every(m.n_faces());
  std::iota(every.begin(), every.end(), std::size_t{0});
  EXPECT_EQ(self_intersecting_faces(m, every), all);
  // The tetrahedra hold faces 0-3, 4-7 and (apart from the others) 8-11.
  EXPECT_TRUE(self_intersecting_faces(m, {0, 1, 2, 3, 8, 9, 10, 11}).empty());  // one of the crossing two
  EXPECT_EQ(self_intersecting_faces(m, {0, 1, 2, 3, 4, 5, 6, 7}), all);
  EXPECT_TRUE(self_intersecting_faces(m, {}).empty());
}

// The test can place the vertices elsewhere than the mesh holds them (at the floats a file rounds
// them to): the third tetrahedron moved onto the first crosses it; the first two moved apart do not.
TEST(CheckMesh, SelfIntersectionsWithTheVerticesPlacedElsewhere) {
  TreeMesh m;
  add_tetrahedron(m, P(0, 0, 0));
  add_tetrahedron(m, P(0.2, 0.2, 0.2));
  add_tetrahedron(m, P(5, 0, 0));
  std::vector<TreeMesh::Point> places;
  for (auto v : m.vertices()) places.push_back(m.point(v));
  EXPECT_EQ(self_intersecting_faces_at(m, places), self_intersecting_faces(m));
  for (std::size_t v = 4; v < 8; ++v) places[v] += P(10, 0, 0);   // the second, away from all
  for (std::size_t v = 8; v < 12; ++v) places[v] -= P(4.8, 0, 0);  // the third, onto the first
  const auto moved = self_intersecting_faces_at(m, places);
  ASSERT_FALSE(moved.empty());
  for (const auto& [a, b] : moved) {
    EXPECT_LT(std::min(a, b), 4u);
    EXPECT_GE(std::max(a, b), 8u);
  }
  const std::vector<std::size_t> first_two{0, 1, 2, 3, 4, 5, 6, 7};
  EXPECT_TRUE(self_intersecting_faces_at(m, places, &first_two).empty());
  places.pop_back();
  EXPECT_THROW(self_intersecting_faces_at(m, places), std::invalid_argument);
}

TEST(CheckMesh, EmptyMeshIsAProblem) {
  EXPECT_EQ(check_mesh(TreeMesh{}).problem(), "the mesh is empty");
}

}  // namespace
}  // namespace treeskel::modeling
