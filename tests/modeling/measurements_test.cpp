#include "model_fixtures.h"
#include "treeskel/modeling/measurements.h"

#include <gtest/gtest.h>

#include <cmath>

namespace treeskel::modeling {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(MeasureTree, StraightTrunk) {
  Skeleton s = test::straight(3.0, 0.1, 30);
  s.offset = Eigen::Vector3d(100, 200, 0);
  const TreeMeasurements m = measure_tree(s, nullptr);
  EXPECT_NEAR(m.height, 3.0, 1e-12);
  ASSERT_TRUE(m.dbh.has_value());
  EXPECT_NEAR(*m.dbh, 0.2, 1e-12);
  EXPECT_NEAR(m.volume, kPi * 0.01 * 3.0, 1e-12);
  EXPECT_NEAR(m.length, 3.0, 1e-12);
  EXPECT_NEAR(m.trunk_length, 3.0, 1e-12);
  EXPECT_EQ(m.branches_by_order, (std::vector<std::size_t>{1}));
  ASSERT_EQ(m.cylinders.size(), 30u);
  EXPECT_EQ(m.cylinders[0].parent, 0u);
  EXPECT_EQ(m.cylinders[1].parent, 1u);
  EXPECT_NEAR(m.cylinders[0].start.x(), 100.0, 1e-12);  // world frame
  EXPECT_NEAR(m.cylinders[5].axis.z(), 1.0, 1e-12);
  EXPECT_EQ(m.cylinders[5].position, 6u);
}

TEST(MeasureTree, YHasATrunkAndOneFirstOrderBranch) {
  const Skeleton s = test::y_shape(0.05, 0.6, 10);
  const TreeMeasurements m = measure_tree(s, nullptr);
  EXPECT_EQ(m.branches_by_order, (std::vector<std::size_t>{1, 1}));
  std::size_t order1 = 0;
  double volume = 0.0;
  for (const auto& c : m.cylinders) {
    order1 += c.order == 1;
    EXPECT_EQ(c.branch, c.order == 0 ? 1u : 2u);
    volume += kPi * c.radius * c.radius * c.length;  // table radii keep the frustum volumes
  }
  EXPECT_EQ(order1, 10u);
  EXPECT_NEAR(volume, m.volume, 1e-12);
  EXPECT_NEAR(m.trunk_length, 2.0, 1e-9);
}

TEST(MeasureTree, NoDbhOnATreeShorterThanBreastHeight) {
  const TreeMeasurements m = measure_tree(test::straight(1.0, 0.1, 10), nullptr);
  EXPECT_FALSE(m.dbh.has_value());
  MeasureOptions o;
  o.breast_height = 0.5;
  EXPECT_NEAR(*measure_tree(test::straight(1.0, 0.1, 10), nullptr, o).dbh, 0.2, 1e-12);
}

}  // namespace
}  // namespace treeskel::modeling
