#include "treeskel/cpc.h"

#include "support/synthetic.h"
#include "treeskel/l1_median.h"
#include "treeskel/pipeline.h"

#include <gtest/gtest.h>

#include <numeric>
#include <random>

namespace treeskel {
namespace {

using test::tube;

/// A short piece of cylinder surface seen from +x only (half of it missing).
PointCloud half_ring(unsigned seed) {
  eval::SurfaceSampling o;
  o.points = 600;
  o.seed = seed;
  o.facing = Eigen::Vector3d::UnitX();
  return eval::sample_cylinders({tube({0, 0, 0}, {0, 0, 0.05}, 0.1)}, o);
}

TEST(Cpc, RecentresAHalfScannedSliceOntoTheAxis) {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const PointCloud cloud = half_ring(seed);
    std::vector<std::uint32_t> idx(cloud.size());
    std::iota(idx.begin(), idx.end(), 0u);
    const Eigen::Vector3d l1 = l1_median(cloud.positions, idx.data(), idx.data() + idx.size());
    const Eigen::Vector3d cpc = cpc_centre(cloud.positions, idx.data(), idx.data() + idx.size(), l1);
    EXPECT_GT(l1.head<2>().norm(), 0.4 * 0.1);
    EXPECT_LT(cpc.head<2>().norm(), 0.1 * 0.1);
  }
}

TEST(Cpc, WeightZeroKeepsTheStart) {
  const PointCloud cloud = half_ring(4);
  std::vector<std::uint32_t> idx(cloud.size());
  std::iota(idx.begin(), idx.end(), 0u);
  CpcOptions off;
  off.weight = 0.0;
  const Eigen::Vector3d start(0.05, 0.0, 0.02);
  EXPECT_EQ(cpc_centre(cloud.positions, idx.data(), idx.data() + idx.size(), start, off), start);
}

TEST(Cpc, FullRingStaysAtItsCentre) {
  eval::SurfaceSampling o;
  o.points = 500;
  const PointCloud cloud = eval::sample_cylinders({tube({0, 0, 0}, {0, 0, 0.05}, 0.1)}, o);
  std::vector<std::uint32_t> idx(cloud.size());
  std::iota(idx.begin(), idx.end(), 0u);
  const Eigen::Vector3d cpc = cpc_centre(cloud.positions, idx.data(), idx.data() + idx.size(), Eigen::Vector3d(0.02, 0.01, 0.02));
  EXPECT_LT(cpc.head<2>().norm(), 0.01 * 0.1);
}

TEST(Cpc, PipelineRecentresAOneSidedCylinder) {
  // A branch scanned from one side: CPC brings the skeleton under 20% of the radius from the axis,
  // while the plain L1-medians stay more than 40% off.
  const auto c = tube({0, 0, 0}, {0, 0, 1}, 0.06);
  eval::SurfaceSampling o;
  o.points = 12000;
  o.facing = Eigen::Vector3d::UnitX();
  const PointCloud cloud = eval::sample_cylinders({c}, o);
  SkeletonOptions with;
  with.use_refine = false;
  SkeletonOptions without = with;
  without.use_cpc = false;
  const double cpc = test::mean_distance_to_axis(extract_skeleton(cloud, with), c);
  const double l1 = test::mean_distance_to_axis(extract_skeleton(cloud, without), c);
  EXPECT_LT(cpc, 0.2 * c.radius_a);
  EXPECT_GT(l1, 0.4 * c.radius_a);
}

// F, its gradient and Hessian written the plain way, one point at a time with Eigen's expressions: the
// library's evaluation, which does two points at a time where the CPU can, must give the same bits.
CpcObjective plain_objective(const std::vector<Eigen::Vector3d>& p, const Eigen::Vector3d& v, double weight) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& q : p) centroid += q;
  centroid /= static_cast<double>(p.size());
  double sum = 0.0, sum_sq = 0.0;
  Eigen::Vector3d u_mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d h_mean = Eigen::Matrix3d::Zero();
  for (const auto& q : p) {
    const Eigen::Vector3d diff = v - q;
    const double d = std::max(diff.norm(), 1e-12);
    sum += d;
    sum_sq += d * d;
    const Eigen::Vector3d u = diff / d;
    u_mean += u;
    h_mean.noalias() += (Eigen::Matrix3d::Identity() - u * u.transpose()) / d;
  }
  const double inv_m = 1.0 / static_cast<double>(p.size());
  CpcObjective e;
  e.mean = sum * inv_m;
  const double lambda = weight / std::max(e.mean, 1e-12);
  e.value = e.mean + lambda * std::max(sum_sq * inv_m - e.mean * e.mean, 0.0);
  u_mean *= inv_m;
  h_mean *= inv_m;
  e.gradient = u_mean + lambda * (2.0 * (v - centroid) - 2.0 * e.mean * u_mean);
  e.hessian = h_mean + lambda * (2.0 * Eigen::Matrix3d::Identity() - 2.0 * u_mean * u_mean.transpose() -
                                 2.0 * e.mean * h_mean);
  return e;
}

TEST(Cpc, ObjectiveGivesThePlainSumsBits) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  for (std::size_t n = 1; n <= 33; ++n) {
    std::vector<Eigen::Vector3d> p;
    for (std::size_t i = 0; i < n; ++i) p.emplace_back(1.0 + 0.2 * g(rng), -4.0 + 0.2 * g(rng), 9.0 + g(rng));
    const Eigen::Vector3d v(1.05, -3.9, 9.2);
    if (n > 4) p[n / 3] = v;  // a point at v: its distance is the floor
    const CpcObjective got = cpc_objective(p, v, 100.0), expected = plain_objective(p, v, 100.0);
    EXPECT_EQ(got.value, expected.value) << n;
    EXPECT_EQ(got.mean, expected.mean) << n;
    for (int r = 0; r < 3; ++r) {
      EXPECT_EQ(got.gradient[r], expected.gradient[r]) << n << " " << r;
      for (int c = 0; c < 3; ++c) EXPECT_EQ(got.hessian(r, c), expected.hessian(r, c)) << n << " " << r << c;
    }
  }
  EXPECT_EQ(cpc_objective({}, Eigen::Vector3d::Zero(), 100.0).value, 0.0);
}

}  // namespace
}  // namespace treeskel
