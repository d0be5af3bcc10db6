// How a fork's join is laid out (modeling/src/joins.h, private to the library), alone: each arm's
// ring pushed out until every ring's plane has the others behind it.
#include "../../modeling/src/joins.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace treeskel::modeling::detail {
namespace {

using Eigen::Vector3d;

/// A straight polyline from `from` to `to`, 11 points, radius `radius`.
Polyline line(const Vector3d& from, const Vector3d& to, double radius) {
  std::vector<Vector3d> points;
  std::vector<double> radii;
  for (int k = 0; k <= 10; ++k) {
    points.push_back(from + (to - from) * (k / 10.0));
    radii.push_back(radius);
  }
  return make_polyline(points, radii, 1e-9);
}

/// A fork at the origin: the base chain from below (chain 0, ending at the fork), two branches
/// leaving it at +-`half_angle` from the vertical (chains 1 and 2).
struct Fork {
  std::vector<Polyline> lines;
  std::vector<int> sides{12, 8, 8};
  Cluster cl;
  explicit Fork(double half_angle, double twig_room = 0.7) {
    lines.push_back(line(Vector3d(0, 0, -1), Vector3d::Zero(), 0.1));
    for (const double sign : {-1.0, 1.0})
      lines.push_back(line(Vector3d::Zero(), Vector3d(sign * std::sin(half_angle), 0, std::cos(half_angle)), 0.07));
    Arm base;
    base.kind = Arm::root;
    base.chain = 0;
    base.forward = false;
    base.available = 0.8;
    cl.arms.push_back(base);
    for (std::size_t c : {1, 2}) {
      Arm twig;
      twig.chain = c;
      twig.available = twig_room;
      cl.arms.push_back(twig);
    }
  }
};

// At a fork of 40 degrees either side the rings are pushed out until each ring's plane has every
// other ring behind it by the clearance; none needs all its room.
TEST(Joins, PlaceRingsLeavesEveryRingBehindTheOthersPlanes) {
  Fork f(0.7);
  std::vector<std::size_t> partner(3, 0);
  ASSERT_FALSE(place_rings(f.cl, 0.4, f.lines, f.sides, 1e-12, partner).has_value());
  for (std::size_t i = 0; i < 3; ++i) {
    const auto [ring, out] = arm_ring(f.cl.arms[i], f.cl.arms[i].d, f.lines[f.cl.arms[i].chain], f.sides[f.cl.arms[i].chain]);
    EXPECT_GE(f.cl.arms[i].d, kFirstRingRadii * f.lines[f.cl.arms[i].chain].r.front() - 1e-12);
    EXPECT_LE(f.cl.arms[i].d, 0.4);
    for (std::size_t j = 0; j < 3; ++j) {
      if (j == i) continue;
      const Ring other = arm_ring(f.cl.arms[j], f.cl.arms[j].d, f.lines[f.cl.arms[j].chain], f.sides[f.cl.arms[j].chain]).first;
      EXPECT_LE(reach_beyond(ring, out, other), -kRingClearanceRadii * ring.radius + 1e-9) << i << " " << j;
    }
  }
  // The base's ring faces down, the branches' up and out.
  EXPECT_LT(arm_ring(f.cl.arms[0], f.cl.arms[0].d, f.lines[0], 12).second.z(), -0.99);
  EXPECT_GT(arm_ring(f.cl.arms[1], f.cl.arms[1].d, f.lines[1], 8).second.z(), 0.7);
}

// At a narrow fork with little room on the twigs, a twig runs out of room first (its overrun counts
// twice), and its partner is the other twig, whose ring crosses its plane.
TEST(Joins, PlaceRingsNamesTheTwigThatRunsOutOfRoom) {
  Fork f(0.05, 0.05);
  std::vector<std::size_t> partner(3, 0);
  const auto failed = place_rings(f.cl, 0.4, f.lines, f.sides, 1e-12, partner);
  ASSERT_TRUE(failed.has_value());
  EXPECT_NE(*failed, 0u);
  EXPECT_EQ(partner[*failed], *failed == 1 ? 2u : 1u);
}

// An arm's ring narrows by its neck, and faces away from the join whichever end of its chain
// leaves it.
TEST(Joins, ArmRingNarrowsByItsNeckAndFacesAwayFromTheJoin) {
  const Polyline pl = line(Vector3d::Zero(), Vector3d(0, 0, 1), 0.1);
  Arm up;
  up.neck = 0.8;
  const auto [ring, out] = arm_ring(up, 0.25, pl, 6);
  EXPECT_NEAR(ring.centre.z(), 0.25, 1e-12);
  EXPECT_NEAR(ring.radius, 0.8 * ring_at(pl, 0.25, 6).radius, 1e-12);
  EXPECT_NEAR(out.z(), 1.0, 1e-12);
  Arm down;
  down.forward = false;
  const auto [back, away] = arm_ring(down, 0.25, pl, 6);
  EXPECT_NEAR(back.centre.z(), 0.75, 1e-12);
  EXPECT_NEAR(away.z(), -1.0, 1e-12);
}

}  // namespace
}  // namespace treeskel::modeling::detail
