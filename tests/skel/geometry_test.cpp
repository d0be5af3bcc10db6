#include "treeskel/geometry.h"

#include <gtest/gtest.h>

#include <random>

namespace treeskel {
namespace {

using Eigen::Vector3d;

TEST(PointSegmentDistance, InsideBeyondAndDegenerate) {
  const Vector3d a(0, 0, 0), b(2, 0, 0);
  EXPECT_DOUBLE_EQ(point_segment_distance(Vector3d(1, 3, 0), a, b), 3.0);
  EXPECT_DOUBLE_EQ(point_segment_distance(Vector3d(5, 4, 0), a, b), 5.0);   // nearest to b
  EXPECT_DOUBLE_EQ(point_segment_distance(Vector3d(-3, 0, 4), a, b), 5.0);  // nearest to a
  EXPECT_DOUBLE_EQ(point_segment_distance(Vector3d(3, 4, 0), a, a), 5.0);   // a point
}

TEST(SegmentSegmentDistance, ExactCases) {
  // Skew lines crossing at a right angle, 2 apart.
  EXPECT_NEAR(segment_segment_distance(Vector3d(-1, 0, 0), Vector3d(1, 0, 0), Vector3d(0, -1, 2), Vector3d(0, 1, 2)), 2.0,
              1e-12);
  // Crossing segments.
  EXPECT_NEAR(segment_segment_distance(Vector3d(-1, 0, 0), Vector3d(1, 0, 0), Vector3d(0, -1, 0), Vector3d(0, 1, 0)), 0.0,
              1e-12);
  // Parallel, overlapping along their length, 3 apart.
  EXPECT_NEAR(segment_segment_distance(Vector3d(0, 0, 0), Vector3d(4, 0, 0), Vector3d(1, 3, 0), Vector3d(6, 3, 0)), 3.0,
              1e-12);
  // Collinear with a gap of 2.
  EXPECT_NEAR(segment_segment_distance(Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(3, 0, 0), Vector3d(5, 0, 0)), 2.0,
              1e-12);
  // The lines' nearest points lie outside both segments: end to end.
  EXPECT_NEAR(segment_segment_distance(Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(2, 1, 0), Vector3d(2, 3, 0)),
              std::sqrt(2.0), 1e-12);
  // A point against a segment, and two points.
  EXPECT_NEAR(segment_segment_distance(Vector3d(1, 2, 0), Vector3d(1, 2, 0), Vector3d(0, 0, 0), Vector3d(2, 0, 0)), 2.0,
              1e-12);
  EXPECT_NEAR(segment_segment_distance(Vector3d(0, 0, 0), Vector3d(0, 0, 0), Vector3d(3, 4, 0), Vector3d(3, 4, 0)), 5.0,
              1e-12);
}

TEST(SegmentSegmentDistance, MatchesDenseSampling) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto random = [&] { return Vector3d(u(rng), u(rng), u(rng)); };
  for (int trial = 0; trial < 200; ++trial) {
    const Vector3d a = random(), b = random(), c = random(), d = random();
    double sampled = 1e300;
    const int n = 400;
    for (int i = 0; i <= n; ++i) sampled = std::min(sampled, point_segment_distance(a + (b - a) * i / n, c, d));
    const double exact = segment_segment_distance(a, b, c, d);
    EXPECT_LE(exact, sampled + 1e-12);
    EXPECT_NEAR(exact, sampled, 2.0 * (b - a).norm() / n);  // sampling's own error
    EXPECT_NEAR(exact, segment_segment_distance(c, d, a, b), 1e-12);  // symmetric
  }
}

TEST(FrustumVolume, CylinderConeAndFrustum) {
  const double pi = 3.14159265358979323846;
  EXPECT_DOUBLE_EQ(frustum_volume(2.0, 2.0, 3.0), pi * 4.0 * 3.0);        // a cylinder
  EXPECT_DOUBLE_EQ(frustum_volume(2.0, 0.0, 3.0), pi * 4.0 * 3.0 / 3.0);  // a cone
  // A frustum is the cone it was cut from less the cone cut off: radii 2 and 1 over 1 is the cone of
  // radius 2 and height 2 less the one of radius 1 and height 1.
  EXPECT_NEAR(frustum_volume(2.0, 1.0, 1.0), pi * (4.0 * 2.0 - 1.0 * 1.0) / 3.0, 1e-12);
  EXPECT_DOUBLE_EQ(frustum_volume(1.0, 2.0, 1.0), frustum_volume(2.0, 1.0, 1.0));
  EXPECT_EQ(frustum_volume(1.0, 1.0, 0.0), 0.0);
}

}  // namespace
}  // namespace treeskel
