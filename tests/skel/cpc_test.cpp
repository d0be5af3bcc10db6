#include "treeskel/cpc.h"

#include "support/synthetic.h"
#include "treeskel/l1_median.h"
#include "treeskel/pipeline.h"

#include <gtest/gtest.h>

#include <numeric>

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

}  // namespace
}  // namespace treeskel
