#include "model_fixtures.h"
#include "treeskel/modeling/measurements.h"
#include "treeskel/modeling/radii.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <random>

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

/// Points on a vertical cylinder of `radius` around (1, 2, z) from z = 0 to `height`, covering the
/// angles [0, `arc`), with Gaussian noise of `noise` across the surface.
PointCloud trunk_cloud(double radius, double height, double arc, double noise, std::size_t count) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(0.0, arc), z(0.0, height);
  std::normal_distribution<double> off(0.0, noise);
  PointCloud cloud;
  for (std::size_t i = 0; i < count; ++i) {
    const double a = angle(rng), r = radius + off(rng);
    cloud.positions.emplace_back(1.0 + r * std::cos(a), 2.0 + r * std::sin(a), z(rng));
  }
  return cloud;
}

/// A skeleton along the cloud's axis (leaning by `lean` over its height), every radius `radius`.
Skeleton trunk_skeleton(double radius, double height, double lean) {
  Skeleton s;
  SkeletonNode root;
  root.position = Eigen::Vector3d(1, 2, 0);
  root.radius = radius;
  s.root = add_node(s, root);
  test::add_run(s, s.root, Eigen::Vector3d(1 + lean, 2, height), radius, 30);
  return s;
}

TEST(MeasureTree, DbhIsFittedToThePointsAtBreastHeight) {
  // A model radius 50% too large, a trunk scanned from one side (200 degrees), 2 mm noise.
  const PointCloud cloud = trunk_cloud(0.1, 3.0, 3.5, 0.002, 6000);
  const Skeleton s = trunk_skeleton(0.15, 3.0, 0.0);
  const TreeMeasurements m = measure_tree(s, &cloud);
  ASSERT_TRUE(m.dbh.has_value());
  EXPECT_EQ(m.dbh_source, DbhSource::points);
  EXPECT_NEAR(*m.dbh, 0.2, 0.004);
  MeasureOptions model_only;
  model_only.dbh_from_points = false;
  const TreeMeasurements from_model = measure_tree(s, &cloud, model_only);
  EXPECT_EQ(from_model.dbh_source, DbhSource::model);
  EXPECT_NEAR(*from_model.dbh, 0.3, 1e-12);
}

TEST(MeasureTree, DbhSliceFollowsTheTrunkNotOneLeaningEdge) {
  const PointCloud cloud = trunk_cloud(0.1, 3.0, 2.0 * kPi, 0.001, 6000);
  Skeleton s = trunk_skeleton(0.1, 3.0, 0.0);
  // The node at 1.4 is knocked 6 cm sideways: the edge through breast height (1.35 here) leans by
  // about 30 degrees, and a slice across it would be an ellipse 15% wider than the trunk.
  for (NodeId v = 0; v < s.node_count(); ++v)
    if (std::abs(s[v].position.z() - 1.4) < 1e-9) s[v].position.x() += 0.06;
  MeasureOptions o;
  o.breast_height = 1.35;
  const TreeMeasurements m = measure_tree(s, &cloud, o);
  EXPECT_EQ(m.dbh_source, DbhSource::points);
  EXPECT_NEAR(*m.dbh, 0.2, 0.004);
}

TEST(MeasureTree, DbhFallsBackToTheModelWithoutAReliableCircle) {
  Skeleton s = trunk_skeleton(0.1, 3.0, 0.0);
  // Too few points in the slice.
  const PointCloud sparse = trunk_cloud(0.1, 3.0, 2.0 * kPi, 0.001, 30);
  EXPECT_EQ(measure_tree(s, &sparse).dbh_source, DbhSource::model);
  // Points on a 0.5 rad arc only.
  const PointCloud narrow = trunk_cloud(0.1, 3.0, 0.5, 0.001, 6000);
  const TreeMeasurements m = measure_tree(s, &narrow);
  EXPECT_EQ(m.dbh_source, DbhSource::model);
  EXPECT_NEAR(*m.dbh, 0.2, 1e-12);
  // No cloud, no tree tall enough.
  EXPECT_EQ(measure_tree(s, nullptr).dbh_source, DbhSource::model);
  EXPECT_EQ(measure_tree(test::straight(1.0, 0.1, 10), &narrow).dbh_source, DbhSource::none);
}

TEST(MeasureTree, DbhIsTakenBelowASwellingAtBreastHeight) {
  // A trunk of radius 0.1 that swells to 0.15 from 1.2 m up (a fork's flare, a burl).
  PointCloud cloud = trunk_cloud(0.1, 1.2, 2.0 * kPi, 0.001, 3000);
  const PointCloud swollen = trunk_cloud(0.15, 1.8, 2.0 * kPi, 0.001, 4500);
  for (const auto& p : swollen.positions) cloud.positions.push_back(p + Eigen::Vector3d(0, 0, 1.2));
  const TreeMeasurements m = measure_tree(trunk_skeleton(0.12, 3.0, 0.0), &cloud);
  EXPECT_EQ(m.dbh_source, DbhSource::points);
  EXPECT_NEAR(*m.dbh, 0.2, 0.004);
  EXPECT_NEAR(m.dbh_height, 1.3 - 0.2, 1e-12);  // the slice under the breast-height one
  EXPECT_NE(dbh_note(m).find("below a swelling"), std::string::npos);
  // A stem that narrows upward, as stems do, is measured at breast height itself.
  const PointCloud plain = trunk_cloud(0.1, 3.0, 2.0 * kPi, 0.001, 6000);
  const TreeMeasurements n = measure_tree(trunk_skeleton(0.12, 3.0, 0.0), &plain);
  EXPECT_NEAR(n.dbh_height, 1.3, 1e-12);
  EXPECT_EQ(dbh_note(n), " (fitted to the points)");
}

TEST(MeasureTree, DbhIsTakenJustBelowWhereNoCircleFitsAtBreastHeight) {
  // A trunk of radius 0.1 seen all round up to 1.2 m, and above only on a 0.5 rad arc (a fork's
  // limbs hide it, or the slice spans a limb): no reliable circle at 1.3, one at 1.1.
  PointCloud cloud = trunk_cloud(0.1, 1.2, 2.0 * kPi, 0.001, 3000);
  const PointCloud arc = trunk_cloud(0.1, 1.8, 0.5, 0.001, 4500);
  for (const auto& p : arc.positions) cloud.positions.push_back(p + Eigen::Vector3d(0, 0, 1.2));
  const TreeMeasurements m = measure_tree(trunk_skeleton(0.12, 3.0, 0.0), &cloud);
  EXPECT_EQ(m.dbh_source, DbhSource::points);
  EXPECT_NEAR(*m.dbh, 0.2, 0.004);
  EXPECT_NEAR(m.dbh_height, 1.3 - 0.2, 1e-12);
  EXPECT_TRUE(m.dbh_unfit_at_breast_height);
  EXPECT_EQ(dbh_note(m), " (fitted to the points at 1.1, where none fits at 1.3)");
}

TEST(MeasureTree, TrunkRisesPastThickClutterAtTheBase) {
  // Ground or roots left in a scan: a chain off the base, thicker than the stem, that stays low.
  Skeleton s;
  SkeletonNode root;
  root.position = Eigen::Vector3d::Zero();
  root.radius = 0.1;
  s.root = add_node(s, root);
  test::add_run(s, s.root, Eigen::Vector3d(2.0, 0.0, 0.1), 0.15, 10);  // clutter, thickening
  test::add_run(s, s.root, Eigen::Vector3d(0.0, 0.0, 3.0), 0.1, 30);   // the stem
  const TreeMeasurements m = measure_tree(s, nullptr);
  ASSERT_TRUE(m.dbh.has_value());
  EXPECT_NEAR(*m.dbh, 0.2, 1e-12);
  EXPECT_NEAR(m.trunk_length, 3.0, 1e-9);
  EXPECT_EQ(m.branches_by_order, (std::vector<std::size_t>{1, 1}));
}

/// The node of `s` nearest to height `z`.
NodeId node_at(const Skeleton& s, double z) {
  NodeId nearest = 0;
  for (NodeId v = 0; v < s.node_count(); ++v)
    if (std::abs(s[v].position.z() - z) < std::abs(s[nearest].position.z() - z)) nearest = v;
  return nearest;
}

/// Gives each point of `cloud` to the node of `s` at its height, unless that node is `skip`.
void share_by_height(Skeleton& s, const PointCloud& cloud, std::optional<NodeId> skip = std::nullopt) {
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (const NodeId v = node_at(s, cloud.positions[i].z()); v != skip) s[v].points.push_back(static_cast<std::uint32_t>(i));
}

TEST(MeasureTree, DbhSliceReachesTheBarkWhereTheModelIsFarTooThin) {
  // The model gives the trunk 0.03 (its share of a fork with ground at the base, say); the bark is
  // at 0.1, outside a slice of twice the model's radius. The circles fitted to the trunk nodes' own
  // points widen the slice.
  const PointCloud cloud = trunk_cloud(0.1, 3.0, 2.0 * kPi, 0.001, 6000);
  Skeleton s = trunk_skeleton(0.03, 3.0, 0.0);
  share_by_height(s, cloud);
  const TreeMeasurements m = measure_tree(s, &cloud);
  EXPECT_EQ(m.dbh_source, DbhSource::points);
  EXPECT_NEAR(*m.dbh, 0.2, 0.004);
  // Without the nodes' points, the slice misses the bark and the model's diameter stands.
  const TreeMeasurements bare = measure_tree(trunk_skeleton(0.03, 3.0, 0.0), &cloud);
  EXPECT_EQ(bare.dbh_source, DbhSource::model);
  EXPECT_NEAR(*bare.dbh, 0.06, 1e-12);
}

TEST(MeasureTree, DbhSliceIsNotWidenedByAnArcBesideTheTrunk) {
  // A trunk of radius 0.12, sparsely scanned, and at breast height a whorl of branches whose points
  // lie on a circle of radius 0.8 centred 0.5 from the axis. The trunk node at 1.3 m holds only the
  // arc of that circle nearest the axis, 0.3 from it (as --complete left a node of TreeLS's spruce
  // once its outer points went to twigs: a circle of 0.39 centred 0.28 off a trunk of 0.12). That
  // circle goes around the whorl, not the node: it must not widen the slice (which then fits the
  // whole whorl, and the DBH is taken under that "swelling"), and the slice at breast height fits
  // the bark.
  PointCloud cloud = trunk_cloud(0.12, 3.0, 2.0 * kPi, 0.001, 1500);
  Skeleton s = trunk_skeleton(0.12, 3.0, 0.0);
  const NodeId at = node_at(s, 1.3);
  share_by_height(s, cloud, at);  // the bark's points to the nodes at their heights, but that one
  for (int i = 0; i < 2000; ++i) {
    const double a = kPi + i * (2.0 * kPi / 2000.0);
    if (std::abs(std::remainder(a - kPi, 2.0 * kPi)) < 0.8)
      s[at].points.push_back(static_cast<std::uint32_t>(cloud.size()));  // 92 degrees, nearest the axis
    cloud.positions.emplace_back(1.5 + 0.8 * std::cos(a), 2.0 + 0.8 * std::sin(a), 1.3);
  }
  const RadiusMeasurement arc = measure_node_radius(s, cloud, at);
  ASSERT_GT(arc.weight, 0.0);
  ASSERT_NEAR(arc.radius, 0.8, 1e-6);
  ASSERT_NEAR(arc.offset, 0.5, 1e-6);
  const TreeMeasurements m = measure_tree(s, &cloud);
  ASSERT_TRUE(m.dbh.has_value());
  EXPECT_EQ(m.dbh_source, DbhSource::points);
  EXPECT_NEAR(*m.dbh, 0.24, 0.01);
  EXPECT_DOUBLE_EQ(m.dbh_height, 1.3);  // at breast height, not under a swelling the whorl made
}

TEST(MeasureTree, DbhSliceThatFitsTheBarkIsNotWidened) {
  // A trunk of radius 0.12 whose model radius is right, and around it at breast height a whorl of
  // branch bases: points on a circle of radius 0.35 around the axis, all of which the trunk node at
  // 1.3 m holds (as a node of TreeLS's spruce moved by the limbs' smoothing came to lie inside a
  // circle of 0.23 around a trunk of 0.175). The node lies at that circle's centre, but the slice of
  // twice the model's radius fits the bark already: widened to the whorl, it fits the whorl.
  PointCloud cloud = trunk_cloud(0.12, 3.0, 2.0 * kPi, 0.001, 1500);
  Skeleton s = trunk_skeleton(0.12, 3.0, 0.0);
  const NodeId at = node_at(s, 1.3);
  share_by_height(s, cloud, at);
  for (int i = 0; i < 600; ++i) {
    const double a = i * (2.0 * kPi / 600.0);
    s[at].points.push_back(static_cast<std::uint32_t>(cloud.size()));
    cloud.positions.emplace_back(1.0 + 0.35 * std::cos(a), 2.0 + 0.35 * std::sin(a), 1.25 + 0.1 * (i % 2));
  }
  const RadiusMeasurement whorl = measure_node_radius(s, cloud, at);
  ASSERT_GT(whorl.weight, 0.0);
  ASSERT_NEAR(whorl.radius, 0.35, 1e-3);
  ASSERT_LT(whorl.offset, 1e-3);
  const TreeMeasurements m = measure_tree(s, &cloud);
  ASSERT_TRUE(m.dbh.has_value());
  EXPECT_EQ(m.dbh_source, DbhSource::points);
  EXPECT_NEAR(*m.dbh, 0.24, 0.01);
  EXPECT_DOUBLE_EQ(m.dbh_height, 1.3);
}

TEST(MeasureTree, DbhCircleMustSurroundTheAxis) {
  // A circle of the model's radius whose centre is 0.09 off the skeleton: it passes next to the axis
  // and is something beside the trunk.
  PointCloud cloud = trunk_cloud(0.1, 3.0, 2.0 * kPi, 0.001, 6000);
  for (auto& p : cloud.positions) p.x() += 0.09;
  const TreeMeasurements m = measure_tree(trunk_skeleton(0.1, 3.0, 0.0), &cloud);
  EXPECT_EQ(m.dbh_source, DbhSource::model);
  // 0.05 off (a trunk scanned from one side pulls the skeleton that far) still counts.
  for (auto& p : cloud.positions) p.x() -= 0.04;
  EXPECT_EQ(measure_tree(trunk_skeleton(0.1, 3.0, 0.0), &cloud).dbh_source, DbhSource::points);
}

}  // namespace
}  // namespace treeskel::modeling
