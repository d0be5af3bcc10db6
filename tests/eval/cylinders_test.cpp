#include "treeskel/eval/cylinders.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

namespace treeskel::eval {
namespace {

std::vector<Cylinder> fork() {
  const Eigen::Vector3d f(0, 0, 1);
  return {{{0, 0, 0}, f, 0.1, 0.08}, {f, {0.5, 0, 1.5}, 0.06, 0.04}, {f, {-0.4, 0.1, 1.6}, 0.05, 0.03}};
}

TEST(Cylinders, PointsLieOnASurfaceAndNeverInsideTheWood) {
  SurfaceSampling s;
  s.points = 5000;
  const auto cylinders = fork();
  const PointCloud cloud = sample_cylinders(cylinders, s);
  ASSERT_EQ(cloud.size(), 5000u);
  for (const auto& p : cloud.positions) {
    double best = 1e9;
    for (const auto& c : cylinders) {
      const double t = std::clamp((p - c.a).dot(c.b - c.a) / (c.b - c.a).squaredNorm(), 0.0, 1.0);
      best = std::min(best, std::abs(distance_to_axis(c, p) - (c.radius_a + t * (c.radius_b - c.radius_a))));
    }
    EXPECT_LT(best, 1e-9);
    for (auto c : cylinders) {  // not inside any cylinder, its own included, beyond rounding
      c.radius_a -= 1e-9;
      c.radius_b -= 1e-9;
      EXPECT_FALSE(inside(c, p));
    }
  }
}

TEST(Cylinders, NoiseStaysWithinItsSpread) {
  SurfaceSampling s;
  s.points = 4000;
  s.noise = 0.002;
  const Cylinder c{{0, 0, 0}, {0, 0, 1}, 0.1, 0.1};
  const PointCloud cloud = sample_cylinders({c}, s);
  double sum_sq = 0.0;
  for (const auto& p : cloud.positions) {
    const double e = distance_to_axis(c, p) - 0.1;
    EXPECT_LT(std::abs(e), 6 * s.noise);
    sum_sq += e * e;
  }
  EXPECT_NEAR(std::sqrt(sum_sq / cloud.size()), s.noise, 0.1 * s.noise);
}

TEST(Cylinders, OneScannerSeesOneSide) {
  SurfaceSampling s;
  s.points = 2000;
  s.facing = Eigen::Vector3d(1, 0, 0);
  const PointCloud cloud = sample_cylinders({{{0, 0, 0}, {0, 0, 1}, 0.1, 0.1}}, s);
  for (const auto& p : cloud.positions) EXPECT_GE(p.x(), -1e-12);
}

TEST(Cylinders, SameSeedSameBytesWhateverTheThreads) {
  SurfaceSampling s;
  s.points = 20000;
  s.seed = 42;
  PointCloud one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = sample_cylinders(fork(), s);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = sample_cylinders(fork(), s);
  }
  EXPECT_EQ(one.positions, two.positions);
  s.seed = 43;
  EXPECT_NE(sample_cylinders(fork(), s).positions, one.positions);
}

}  // namespace
}  // namespace treeskel::eval
