// One attempt of the sweep, as a soup of parts (modeling/src/attempt.h, private to the library),
// alone: the mesh it makes, the parts that cross, and how far a part thins to clear another.
#include "../../modeling/src/attempt.h"

#include <gtest/gtest.h>

#include <array>
#include <vector>

namespace treeskel::modeling::detail {
namespace {

using Eigen::Vector3d;

/// Adds the triangle (a, b, c) to `attempt` as part `part` (created if new) with the rings `rings`,
/// owned by node `owner` of radius `radius`.
void add_triangle(Attempt& attempt, const Vector3d& a, const Vector3d& b, const Vector3d& c, std::size_t part,
                  std::vector<std::size_t> rings = {}, NodeId owner = 0, double radius = 0.1) {
  const std::size_t first = attempt.vertices.size();
  attempt.vertices.insert(attempt.vertices.end(), {a, b, c});
  attempt.faces.push_back({first, first + 1, first + 2});
  attempt.face_owner.push_back(owner);
  attempt.owner_radius.push_back(radius);
  attempt.face_part.push_back(part);
  if (attempt.part_rings.size() <= part) attempt.part_rings.resize(part + 1);
  attempt.part_rings[part] = std::move(rings);
}

// Two parts cross when a face of one meets a face of the other, unless they share a ring (a band
// and the next one meet at their ring); parts whose boxes meet but whose faces do not, do not.
TEST(Attempt, CrossingPartsAreThoseWhoseFacesMeetAndShareNoRing) {
  Attempt attempt;
  add_triangle(attempt, {0, 0, 0}, {2, 0, 0}, {0, 2, 0}, 0, {7});
  add_triangle(attempt, {0.5, 0.5, -1}, {0.5, 0.5, 1}, {0.6, 0.4, 1}, 1, {8});  // through part 0
  add_triangle(attempt, {1.5, 1.5, -1}, {1.5, 1.5, 1}, {1.6, 1.4, 1}, 2, {9});  // in part 0's box, past its face
  auto pairs = crossing_parts(attempt);
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0], (std::pair<std::size_t, std::size_t>{0, 1}));
  attempt.part_rings[1] = {7};  // now part 1 shares part 0's ring
  EXPECT_TRUE(crossing_parts(attempt).empty());
}

// A tube's part thins by 0.97 (d - r_y) / r_x to clear another at axis distance d, at most to 0.95;
// a hull has no axis, so no factor.
TEST(Attempt, ClearingFactorFollowsTheAxesAndRadii) {
  Attempt attempt;
  attempt.part_axis.resize(4);
  attempt.part_axis[0] = {Vector3d(0, 0, 0), Vector3d(0, 0, 1), 0.2, 0};
  attempt.part_axis[1] = {Vector3d(0.25, 0, 0), Vector3d(0.25, 0, 1), 0.1, 1};
  attempt.part_axis[2] = {Vector3d(2, 0, 0), Vector3d(2, 0, 1), 0.1, 2};
  attempt.part_axis[3] = {Vector3d(3, 0, 0), Vector3d(3, 0, 1), -1.0, -1};  // a hull
  attempt.tube_parts.resize(3);
  for (std::size_t t = 0; t < 3; ++t) attempt.tube_parts[t] = {{-1, -1}, t, t + 1};
  ASSERT_TRUE(clearing_factor(attempt, 0, 1).has_value());
  EXPECT_NEAR(*clearing_factor(attempt, 0, 1), 0.97 * (0.25 - 0.1) / 0.2, 1e-12);
  EXPECT_NEAR(*clearing_factor(attempt, 1, 0), 0.97 * (0.25 - 0.2) / 0.1, 1e-12);
  EXPECT_NEAR(*clearing_factor(attempt, 0, 2), 0.95, 1e-12);  // 0.97 (2 - 0.1) / 0.2 is above the cap
  EXPECT_FALSE(clearing_factor(attempt, 0, 3).has_value());
  EXPECT_FALSE(clearing_factor(attempt, 3, 0).has_value());
}

// A closed soup becomes a closed mesh; a face OpenMesh refuses (a third face on one edge) asks for
// its owner to be thinned, and no mesh is made.
TEST(Attempt, AssembleMakesTheMeshOrNamesTheBranchToThin) {
  const std::array<Vector3d, 4> p{Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(0, 1, 0), Vector3d(0, 0, 1)};
  Attempt attempt;
  attempt.vertices.assign(p.begin(), p.end());
  attempt.faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  attempt.face_owner = {1, 1, 2, 2};
  attempt.owner_radius = {0.1, 0.1, 0.2, 0.2};
  attempt.face_part = {0, 0, 1, 1};
  auto mesh = assemble(attempt);
  ASSERT_TRUE(mesh.has_value());
  EXPECT_EQ(mesh->n_faces(), 4u);
  EXPECT_TRUE(check_mesh(*mesh).ok()) << check_mesh(*mesh).problem();
  EXPECT_TRUE(attempt.face_part.empty());  // no longer in step with the faces
  EXPECT_EQ(attempt.face_owner, (std::vector<NodeId>{1, 1, 2, 2}));

  attempt.vertices.push_back(Vector3d(1, 1, 1));
  attempt.faces.push_back({0, 1, 4});  // a third face on edge 0-1
  attempt.face_owner = {1, 1, 2, 2, 5};
  attempt.owner_radius = {0.1, 0.1, 0.2, 0.2, 0.3};
  EXPECT_FALSE(assemble(attempt).has_value());
  EXPECT_EQ(attempt.shrink, std::vector<NodeId>{5});
}

}  // namespace
}  // namespace treeskel::modeling::detail
