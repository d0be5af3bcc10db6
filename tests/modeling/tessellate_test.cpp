// The triangles of one attempt of the sweep (modeling/src/tessellate.h, private to the library),
// alone: a tube's cap, bands and cone, and a join's hull.
#include "../../modeling/src/tessellate.h"

#include <gtest/gtest.h>

#include <vector>

namespace treeskel::modeling::detail {
namespace {

using Eigen::Vector3d;

/// A ring of `sides` sides and radius `radius` across the z axis at height `z`.
Ring ring_at_height(double z, double radius, int sides = 6) {
  Ring ring;
  ring.centre = Vector3d(0, 0, z);
  ring.normal = Vector3d::UnitZ();
  ring.u = Vector3d::UnitX();
  ring.radius = radius;
  ring.sides = sides;
  return ring;
}

// A tube from a flat base to a tip: a cap, a band between each two rings and a cone, each a part
// of its own with the rings it touches; one closed surface, every face owned by the tube's branch.
TEST(Tessellate, ATubeIsACapBandsAndACone) {
  Tube tube;
  tube.owner = 7;
  tube.rings = {ring_at_height(0.0, 0.1), ring_at_height(0.5, 0.08), ring_at_height(1.0, 0.05)};
  tube.base = tube.tip = true;
  tube.apex_height = 0.05;
  HullCache hulls;
  Attempt attempt;
  tessellate({}, {tube}, hulls, attempt);
  EXPECT_EQ(attempt.faces.size(), 6u + 2u * 2u * 6u + 6u);
  EXPECT_EQ(attempt.vertices.size(), 3u * 6u + 2u);  // the rings, the cap's centre, the apex
  ASSERT_EQ(attempt.part_rings.size(), 4u);
  EXPECT_EQ(attempt.part_rings[1], (std::vector<std::size_t>{0, 7}));  // the first band: ring 0, ring 1 after the centre
  ASSERT_EQ(attempt.tube_parts.size(), 1u);
  EXPECT_EQ(attempt.tube_parts[0].first_part, 0u);
  EXPECT_EQ(attempt.tube_parts[0].end_part, 4u);
  EXPECT_NEAR(attempt.vertices.back().z(), 1.05, 1e-12);  // the apex
  for (NodeId owner : attempt.face_owner) EXPECT_EQ(owner, 7u);
  const auto mesh = assemble(attempt);
  ASSERT_TRUE(mesh.has_value());
  const MeshCheck check = check_mesh(*mesh);
  EXPECT_TRUE(check.ok()) << check.problem();
  EXPECT_GT(check.volume, 0.0);  // outward
}

// A join's surface is the hull of its rings less their own faces; a required point inside the hull
// means its rings do not fit (its top is to be thinned and it adds no face), an optional one is left
// out.
TEST(Tessellate, AJoinIsTheHullOfItsRingsOrAsksForItsTopToBeThinned) {
  Join join;
  join.rings = {ring_at_height(0.0, 1.0), ring_at_height(1.0, 1.0)};
  join.top = 3;
  join.radius = 1.0;
  Attempt attempt;
  for (const Ring& ring : join.rings) join.first_vertex.push_back(add_ring(attempt.vertices, ring));
  attempt.vertices.push_back(Vector3d(0, 0, 0.5));  // inside the hull
  join.points = {{attempt.vertices.back(), attempt.vertices.size() - 1}};
  HullCache hulls;
  Attempt inside = attempt;
  tessellate({join}, {}, hulls, inside);
  EXPECT_TRUE(inside.faces.empty());
  EXPECT_EQ(inside.shrink, std::vector<NodeId>{3});
  join.optional = 1;
  tessellate({join}, {}, hulls, attempt);
  EXPECT_TRUE(attempt.shrink.empty());
  EXPECT_EQ(attempt.faces.size(), 12u);  // the band of two hexagons; their own faces left open
  for (const auto& f : attempt.faces)
    for (std::size_t v : f) EXPECT_LT(v, 12u);  // the optional point is on no face
  EXPECT_EQ(hulls.size(), 2u);  // one hull a set of points: computed once each
  tessellate({join}, {}, hulls, attempt);
  EXPECT_EQ(hulls.size(), 2u);
}

}  // namespace
}  // namespace treeskel::modeling::detail
