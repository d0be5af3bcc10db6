// The sweep's tube geometry (modeling/src/tube.h, private to the library), alone.
#include "../../modeling/src/tube.h"
#include "treeskel/error.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <vector>

namespace treeskel::modeling::detail {
namespace {

using Eigen::Vector3d;

// A regular n-gon of circumradius r * area_factor(n) has the area of the circle of radius r.
TEST(Tube, AreaFactorKeepsTheCirclesArea) {
  for (int n : {3, 4, 6, 12, 48}) {
    const double R = area_factor(n);
    EXPECT_NEAR(0.5 * n * R * R * std::sin(2.0 * kPi / n), kPi, 1e-12) << n;
  }
  EXPECT_GT(area_factor(3), area_factor(6));
  EXPECT_NEAR(area_factor(1000), 1.0, 1e-5);
}

TEST(Tube, TransportKeepsTheFrameAcrossAndUnit) {
  const Vector3d u(1, 0, 0), from(0, 0, 1);
  for (const Vector3d& to : {Vector3d(0, 1, 1).normalized(), Vector3d(1, 0, 0), Vector3d(0, 0, -1)}) {
    const Vector3d v = transport(u, from, to);
    EXPECT_NEAR(v.norm(), 1.0, 1e-12);
    EXPECT_NEAR(v.dot(to), 0.0, 1e-12);
  }
  // No turn, no change.
  EXPECT_TRUE(transport(u, from, from).isApprox(u, 1e-12));
}

TEST(Tube, PolylineMergesRepeatsAndDropsFoldsButKeepsTheEnds) {
  const std::vector<Vector3d> points{{0, 0, 0}, {0, 0, 1e-9}, {0, 0, 1}, {0, 0, 0.5}, {0, 0, 2}, {0, 0, 2 + 1e-9}};
  const std::vector<double> radii{0.2, 0.2, 0.1, 0.1, 0.05, 0.04};
  const Polyline pl = make_polyline(points, radii, 1e-6);
  ASSERT_GE(pl.p.size(), 2u);
  EXPECT_EQ(pl.p.front(), Vector3d(0, 0, 0));
  EXPECT_EQ(pl.p.back(), Vector3d(0, 0, 2 + 1e-9));  // the true end, not the merged one
  EXPECT_EQ(pl.r.back(), 0.04);
  for (std::size_t i = 1; i < pl.p.size(); ++i) {
    EXPECT_GT((pl.p[i] - pl.p[i - 1]).z(), 0.0) << "the polyline still folds back at " << i;
    EXPECT_GT(pl.s[i], pl.s[i - 1]);
  }
  EXPECT_NEAR(pl.length(), 2.0, 1e-6);
  for (std::size_t i = 0; i < pl.p.size(); ++i) {
    EXPECT_NEAR(pl.t[i].norm(), 1.0, 1e-12);
    EXPECT_NEAR(pl.u[i].dot(pl.t[i]), 0.0, 1e-12);
  }
}

TEST(Tube, PolylineKeepsItsPointsARadiusApart) {
  // A path that zigzags across its own radius (0.1) in steps of 0.02, and steps down and up again.
  std::vector<Vector3d> points;
  for (int i = 0; i <= 50; ++i) points.emplace_back(i % 2 ? 0.03 : -0.03, 0.0, 0.02 * i);
  for (double z : {0.96, 0.92, 0.9, 0.95, 1.0, 1.05}) points.emplace_back(0.0, 0.0, z);
  points.emplace_back(0.0, 0.0, 1.6);
  const std::vector<double> radii(points.size(), 0.1);
  const Polyline pl = make_polyline(points, radii, 1e-9);
  EXPECT_EQ(pl.p.front(), points.front());
  EXPECT_EQ(pl.p.back(), points.back());
  for (std::size_t i = 1; i < pl.p.size(); ++i) {
    EXPECT_GE((pl.p[i] - pl.p[i - 1]).norm(), kStepRadii * 0.1) << "points " << i - 1 << " and " << i;
    EXPECT_GT(pl.p[i].z(), pl.p[i - 1].z()) << "the polyline still steps down at " << i;
  }
  // Nothing of a path whose points are already that far apart is dropped.
  const Polyline sparse = make_polyline({{0, 0, 0}, {0.3, 0, 1}, {0, 0, 2}, {0.3, 0, 3}}, {0.1, 0.1, 0.1, 0.1}, 1e-9);
  EXPECT_EQ(sparse.p.size(), 4u);
}

// A hairpin within the branch's own radius (0.05): down 0.2, across the bottom in a step of 0.06 (90
// degrees), then up and away at 45 degrees; neither turn reaches the 120-degree rule, but over the
// step across the path turns back by 135 degrees, and its tube would pass through itself. The two
// points of that step go: the path runs from the last point down to the first one up. With a
// radius under half the step, nothing goes.
TEST(Tube, PolylineDropsAHairpinWithinTwoRadii) {
  const std::vector<Vector3d> points{{0, 0, 0.3}, {0, 0, 0.2}, {0, 0, 0.1}, {0.06, 0, 0.1}, {0.16, 0, 0.2}, {0.26, 0, 0.3}};
  const Polyline pl = make_polyline(points, std::vector<double>(points.size(), 0.05), 1e-9);
  ASSERT_EQ(pl.p.size(), 4u);
  EXPECT_EQ(pl.p[1], points[1]);
  EXPECT_EQ(pl.p[2], points[4]);
  EXPECT_EQ(pl.p.back(), points.back());
  const Polyline thin = make_polyline(points, std::vector<double>(points.size(), 0.02), 1e-9);
  EXPECT_EQ(thin.p.size(), points.size());
}

TEST(Tube, RingAtInterpolatesAndClamps) {
  const Polyline pl = make_polyline({{0, 0, 0}, {0, 0, 1}, {1, 0, 1}}, {0.2, 0.1, 0.1}, 1e-9);
  const Ring mid = ring_at(pl, 0.5, 8);
  EXPECT_TRUE(mid.centre.isApprox(Vector3d(0, 0, 0.5), 1e-12));
  EXPECT_NEAR(mid.radius, 0.15 * area_factor(8), 1e-12);
  EXPECT_TRUE(mid.normal.isApprox(Vector3d(0, 0, 1), 1e-12));
  for (int k = 0; k < 8; ++k) {
    EXPECT_NEAR((mid.vertex(k) - mid.centre).norm(), mid.radius, 1e-12);
    EXPECT_NEAR((mid.vertex(k) - mid.centre).dot(mid.normal), 0.0, 1e-12);
  }
  const Ring before = ring_at(pl, -3.0, 8), after = ring_at(pl, 99.0, 8);
  EXPECT_TRUE(before.centre.isApprox(Vector3d(0, 0, 0)));
  EXPECT_TRUE(after.centre.isApprox(Vector3d(1, 0, 1)));
  EXPECT_TRUE(after.normal.isApprox(Vector3d(1, 0, 0), 1e-12));
  // Points that all merge leave one point: no ring (an error, which the sweep can act on).
  const Polyline point = make_polyline({{5, 5, 5}, {5, 5, 5 + 1e-12}}, {0.1, 0.1}, 1e-9);
  ASSERT_EQ(point.p.size(), 1u);
  EXPECT_THROW(ring_at(point, 0.0, 8), Error);
}

TEST(Tube, CompatibleRingsLieAheadOfOneAnother) {
  Ring a;
  a.centre = {0, 0, 0};
  a.normal = {0, 0, 1};
  a.u = {1, 0, 0};
  a.radius = 0.1;
  a.sides = 8;
  Ring b = a;
  b.centre = {0, 0, 1};
  EXPECT_TRUE(compatible(a, b, 0.01));
  EXPECT_FALSE(compatible(b, a, 0.01));  // the wrong way round
  // Tilted by 90 degrees just ahead: its circle reaches back across a's plane.
  Ring tilted = b;
  tilted.centre = {0, 0, 0.05};
  tilted.normal = {1, 0, 0};
  tilted.u = {0, 0, 1};
  EXPECT_FALSE(compatible(a, tilted, 0.0));
  EXPECT_NEAR(reach_beyond(a, -a.normal, tilted), 0.05, 1e-12);  // 0.1 - 0.05 behind a's plane
}

/// A straight branch along z from 0 to 4, a point every 0.2, radius 0.1 throughout; the point
/// `bumped` (if any) moved sideways by `bump`.
Polyline straight_branch(std::size_t bumped = 0, double bump = 0.0) {
  std::vector<Vector3d> points;
  std::vector<double> radii;
  for (int k = 0; k <= 20; ++k) {
    points.emplace_back(0.0, 0.0, 0.2 * k);
    radii.push_back(0.1);
  }
  points[bumped].x() += bump;
  return make_polyline(points, radii, 1e-9);
}

// Where the branch runs straight the tube lays a ring only where a band would grow longer than the
// rule allows; with no such bound, none between its ends.
TEST(Tube, LayRingsPutsRingsOnAStraightRunOnlyWhereABandWouldGrowTooLong) {
  const Polyline pl = straight_branch();
  ASSERT_EQ(pl.p.size(), 21u);
  const Ring first = ring_at(pl, 0.0, 6), last = ring_at(pl, pl.length(), 6);
  RingRule rule;
  rule.eps = 1e-9;
  std::vector<Ring> rings;
  ASSERT_TRUE(lay_rings(pl, 0.0, pl.length(), first, last, 6, rule, rings));
  EXPECT_EQ(rings.size(), 1u);
  rule.longest_band = 0.5;
  ASSERT_TRUE(lay_rings(pl, 0.0, pl.length(), first, last, 6, rule, rings));
  ASSERT_EQ(rings.size(), 10u);  // at 0, 0.4, ..., 3.6: the band to the next point would be 0.6
  for (std::size_t k = 0; k < rings.size(); ++k) EXPECT_NEAR(rings[k].centre.z(), 0.4 * double(k), 1e-9) << k;
}

// A point of the branch more than kStrayRadii of its radius off the straight axis keeps its ring
// (the tube would leave the skeleton outside); one less far off does not.
TEST(Tube, StraightPastOnlyWhereTheSkeletonStaysNearTheAxis) {
  for (const double bump : {0.4, 0.6}) {
    const Polyline pl = straight_branch(10, bump * 0.1);
    const Ring prev = ring_at(pl, 0.0, 6), last = ring_at(pl, pl.length(), 6);
    RingRule rule;
    rule.eps = 1e-9;
    EXPECT_EQ(straight_past(pl, prev, 0.0, 10, pl.length(), last, rule), bump == 0.4) << bump;  // kStrayRadii 0.5
    EXPECT_TRUE(straight_past(pl, prev, 0.0, 8, pl.length(), last, rule)) << bump;  // not that far yet
  }
  // A radius off the straight taper by more than kTaperShare keeps the ring too.
  std::vector<Vector3d> points;
  std::vector<double> radii;
  for (int k = 0; k <= 20; ++k) {
    points.emplace_back(0.0, 0.0, 0.2 * k);
    radii.push_back(k == 10 ? 0.105 : 0.1);
  }
  const Polyline swollen = make_polyline(points, radii, 1e-9);
  RingRule rule;
  rule.eps = 1e-9;
  EXPECT_FALSE(straight_past(swollen, ring_at(swollen, 0.0, 6), 0.0, 10, swollen.length(), ring_at(swollen, swollen.length(), 6), rule));
}

TEST(Tube, TipArcLeavesTheTipsRingHalfARadiusShortOfItsEndAtMost) {
  const Polyline pl = straight_branch();
  EXPECT_NEAR(tip_arc(pl, 0.0), 4.0 - 0.05, 1e-12);  // 0.6 of the way would be 2.4: the tip keeps its length
  EXPECT_NEAR(tip_arc(pl, 3.99), 3.99 + 0.6 * 0.01, 1e-12);
}

}  // namespace
}  // namespace treeskel::modeling::detail
