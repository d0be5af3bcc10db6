#include "modeling/model_fixtures.h"
#include "treeskel/modeling/coverage.h"
#include "treeskel/modeling/sweep.h"

#include <gtest/gtest.h>

namespace treeskel::modeling {
namespace {

TEST(Coverage, ASweptBranchHoldsItsWholeSkeleton) {
  const Skeleton s = test::straight(2.0, 0.05, 20);
  const TreeMesh mesh = sweep_mesh(s);
  const SkeletonCoverage c = skeleton_coverage(s, mesh);
  EXPECT_NEAR(c.length, 2.0, 1e-12);
  EXPECT_NEAR(c.share(), 1.0, 1e-9);
}

TEST(Coverage, AMeshOfHalfTheBranchHoldsHalfItsLength) {
  const Skeleton whole = test::straight(2.0, 0.05, 20);
  const TreeMesh half = sweep_mesh(test::straight(1.0, 0.05, 10));
  const SkeletonCoverage c = skeleton_coverage(whole, half);
  // The half mesh ends in a cone at 1.0: within one sample step of a half.
  EXPECT_NEAR(c.share(), 0.5, 0.01);
  EXPECT_DOUBLE_EQ(skeleton_coverage(whole, TreeMesh{}).share(), 0.0);
}

TEST(Coverage, SurfaceDistancesOfAxisAndOutsidePoints) {
  const TreeMesh mesh = sweep_mesh(test::straight(2.0, 0.1, 20));
  const std::vector<Eigen::Vector3d> points{{0, 0, 1}, {1, 0, 1}};
  const auto d = surface_distances(mesh, points);
  ASSERT_EQ(d.size(), 2u);
  // Polygons keep the circle's area: their sides lie a little inside the circle, their corners out.
  EXPECT_NEAR(d[0], 0.1, 0.01);
  EXPECT_NEAR(d[1], 0.9, 0.01);
  EXPECT_DOUBLE_EQ(share_within(d, 0.5), 0.5);
  EXPECT_DOUBLE_EQ(share_within({}, 1.0), 0.0);
}

}  // namespace
}  // namespace treeskel::modeling
