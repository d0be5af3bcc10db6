#include "model_fixtures.h"
#include "treeskel/modeling/base.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace treeskel::modeling {
namespace {

/// A trunk of radius 0.1 along `axis` from the origin, 2 m long, nodes 5 cm apart; the root's points
/// lie on its bark from `from` to `to` along the axis (the root is at 0).
struct Trunk {
  Skeleton skeleton;
  PointCloud cloud;
};

Trunk trunk(const Eigen::Vector3d& axis, double from, double to, int points = 200) {
  Trunk t;
  t.skeleton = test::lone_root(0.1);
  test::add_run(t.skeleton, t.skeleton.root, 2.0 * axis.normalized(), 0.1, 40);
  const Eigen::Vector3d a = axis.normalized();
  const Eigen::Vector3d u = a.unitOrthogonal(), v = a.cross(u);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI), along(from, to);
  for (int i = 0; i < points; ++i) {
    const double phi = angle(rng);
    t.cloud.positions.push_back(along(rng) * a + 0.1 * (std::cos(phi) * u + std::sin(phi) * v));
    t.skeleton[t.skeleton.root].points.push_back(static_cast<std::uint32_t>(i));
  }
  return t;
}

TEST(Base, TheRootGoesDownItsTrunkToWhereItsPointsEnd) {
  for (const Eigen::Vector3d axis : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 0, 1)}) {
    Trunk t = trunk(axis, -0.12, 0.08);
    const double moved = reach_down(t.skeleton, t.cloud);
    // The points' distances below the root spread evenly from -0.08 to 0.12: their 95th percentile
    // is about 0.11.
    EXPECT_NEAR(moved, 0.11, 0.008);
    const Eigen::Vector3d at = t.skeleton[t.skeleton.root].position;
    EXPECT_NEAR(at.norm(), moved, 1e-12);
    EXPECT_NEAR(at.normalized().dot(-axis.normalized()), 1.0, 1e-9);  // straight down the axis
    // The other nodes stay.
    EXPECT_EQ(t.skeleton[1].position, (2.0 / 40) * axis.normalized());
  }
}

TEST(Base, NothingMovesWithoutPointsBelowTheRoot) {
  Trunk above = trunk(Eigen::Vector3d(0, 0, 1), 0.01, 0.1);
  EXPECT_EQ(reach_down(above.skeleton, above.cloud), 0.0);
  EXPECT_EQ(above.skeleton[above.skeleton.root].position, Eigen::Vector3d::Zero());
  Trunk few = trunk(Eigen::Vector3d(0, 0, 1), -0.1, 0.0, 2);
  EXPECT_EQ(reach_down(few.skeleton, few.cloud), 0.0);
  Trunk none = trunk(Eigen::Vector3d(0, 0, 1), -0.1, 0.0, 0);
  EXPECT_EQ(reach_down(none.skeleton, none.cloud), 0.0);
}

TEST(Base, ARootBesideItsTrunkGoesOntoItsAxis) {
  // The level sets put the root 6 cm to the side, at the median of a flared base.
  Trunk t = trunk(Eigen::Vector3d(0, 0, 1), -0.1, 0.05);
  t.skeleton[t.skeleton.root].position = Eigen::Vector3d(0.06, 0.0, 0.0);
  const double moved = reach_down(t.skeleton, t.cloud);
  const Eigen::Vector3d at = t.skeleton[t.skeleton.root].position;
  EXPECT_LT(at.head<2>().norm(), 0.01);
  EXPECT_NEAR(at.z(), -0.0925, 0.008);  // the 95th percentile of 0.1 below and 0.05 above
  EXPECT_NEAR(moved, (at - Eigen::Vector3d(0.06, 0.0, 0.0)).norm(), 1e-12);
}

TEST(Base, ARootWhoseTrunkRunsSidewaysStays) {
  // A path that leaves the root sideways (along the ground, 0.6 m) before it rises 2 m: the axis near
  // the root is horizontal, not the way down.
  Skeleton s = test::lone_root(0.1);
  const NodeId corner = test::add_run(s, s.root, Eigen::Vector3d(0.6, 0, 0), 0.1, 12);
  test::add_run(s, corner, Eigen::Vector3d(0.6, 0, 2.0), 0.1, 40);
  PointCloud cloud;
  for (int i = 0; i < 50; ++i) {
    cloud.positions.emplace_back(-0.002 * i, 0.05 * std::cos(i), 0.05 * std::sin(i));
    s[s.root].points.push_back(static_cast<std::uint32_t>(i));
  }
  EXPECT_EQ(reach_down(s, cloud), 0.0);
  EXPECT_EQ(s[s.root].position, Eigen::Vector3d::Zero());
}

TEST(Base, ARootFarAboveItsPointsStays) {
  // Points a metre below a root of radius 0.1: not the trunk's base; nothing moves.
  Trunk deep = trunk(Eigen::Vector3d(0, 0, 1), -1.0, -0.9);
  EXPECT_EQ(reach_down(deep.skeleton, deep.cloud), 0.0);
  EXPECT_EQ(deep.skeleton[deep.skeleton.root].position, Eigen::Vector3d::Zero());
}

TEST(Base, GroundAroundALeaningTrunkDoesNotCountForItsBase) {
  // A trunk leaning 30 degrees whose bark ends 8 cm below the root, on a ground of points 1 m around
  // it 5 cm below the root. Down the leaning axis, the ground on the side it leans from lies up to
  // 0.5 m away; the base goes to where the bark ends.
  const Eigen::Vector3d axis(0.5, 0.0, std::sqrt(0.75));
  Trunk t = trunk(axis, -0.08, 0.1);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> side(-1.0, 1.0);
  for (int i = 0; i < 400; ++i) {
    t.skeleton[t.skeleton.root].points.push_back(static_cast<std::uint32_t>(t.cloud.size()));
    t.cloud.positions.emplace_back(side(rng), side(rng), -0.05);
  }
  const double moved = reach_down(t.skeleton, t.cloud);
  EXPECT_NEAR(moved, 0.071, 0.008);  // the 95th percentile of the bark's 0.08 below and 0.1 above
  double lowest = 0.0;
  for (const auto& p : t.cloud.positions) lowest = std::min(lowest, p.z());
  EXPECT_GT(t.skeleton[t.skeleton.root].position.z(), lowest);
}

}  // namespace
}  // namespace treeskel::modeling
