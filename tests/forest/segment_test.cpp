// Segmentation: a synthetic plot's trees found point by point, whatever the thread count; parts apart
// from the trees joined or left by the rules; the crown base of a tree whose crown starts at 4 m.
#include "treeskel/eval/plots.h"
#include "treeskel/forest/segment.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <random>

namespace treeskel::forest {
namespace {

eval::PlotOptions small_plot() {
  eval::PlotOptions o;
  o.seed = 4;
  o.trees = 4;
  o.width = 10.0;
  o.shrubs = 4;
  o.points_per_tree = 12000;
  return o;
}

TEST(SegmentTrees, ASyntheticPlotsTreesPointByPoint) {
  const eval::SyntheticPlot plot = eval::make_plot(small_plot());
  const Ground ground = classify_ground(plot.cloud);
  const std::vector<Stem> stems = find_stems(plot.cloud, ground);
  const Segmentation seg = segment_trees(plot.cloud, ground, stems);
  ASSERT_EQ(seg.tree.size(), plot.cloud.size());
  std::vector<Eigen::Vector2d> centres;
  for (const auto& s : stems) centres.push_back(s.centre);
  const eval::PlotScore score = eval::score_plot(plot, centres, seg.tree);
  EXPECT_EQ(score.stem_recall, 1.0);
  EXPECT_EQ(score.stem_precision, 1.0);
  EXPECT_GT(score.mean_iou, 0.8);
  EXPECT_LT(score.others_in_trees, 0.02);
  for (std::uint32_t t : seg.tree) ASSERT_LE(t, stems.size());
  // The ground's points are in no tree but for the bases of the stems.
  std::size_t ground_in_trees = 0;
  for (std::size_t p = 0; p < plot.cloud.size(); ++p) ground_in_trees += ground.is_ground[p] && seg.tree[p] != 0;
  EXPECT_EQ(ground_in_trees, seg.stem_base_points);

  // One thread or all: the same labels.
  const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  EXPECT_EQ(segment_trees(plot.cloud, ground, stems).tree, seg.tree);
  EXPECT_EQ(find_stems(plot.cloud, classify_ground(plot.cloud)).size(), stems.size());
}

/// One stem at the origin: a trunk from the ground to 4 m, a crown spreading from 4 m to 6 m.
PointCloud tree_with_crown(std::vector<Stem>& stems, Ground& ground) {
  PointCloud cloud;
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 4000; ++i) {
    const double a = 2 * M_PI * u(rng);
    cloud.positions.emplace_back(0.1 * std::cos(a), 0.1 * std::sin(a), 4.0 * u(rng));
  }
  for (int i = 0; i < 4000; ++i) {
    const double a = 2 * M_PI * u(rng), r = 2.5 * std::sqrt(u(rng));
    cloud.positions.emplace_back(r * std::cos(a), r * std::sin(a), 4.0 + 2.0 * u(rng));
  }
  ground.terrain.nx = ground.terrain.ny = 1;
  ground.terrain.origin = {-10, -10};
  ground.terrain.cell = 20;
  ground.terrain.z = {0.0};
  ground.is_ground.assign(cloud.size(), 0);
  for (const auto& p : cloud.positions) ground.height.push_back(static_cast<float>(p.z()));
  stems = {Stem{{0.0, 0.0}, 0.0, 0.1, 100}};
  return cloud;
}

TEST(SegmentTrees, APartApartJoinsTheNearTreeUnlessItIsLowOrFar) {
  std::vector<Stem> stems;
  Ground ground;
  PointCloud cloud = tree_with_crown(stems, ground);
  const std::size_t tree_points = cloud.size();
  auto blob = [&](const Eigen::Vector3d& at) {
    for (int i = 0; i < 50; ++i) {
      cloud.positions.push_back(at + Eigen::Vector3d(0.01 * (i % 5), 0.01 * (i / 5 % 5), 0.01 * (i / 25)));
      ground.is_ground.push_back(0);
      ground.height.push_back(static_cast<float>(at.z()));
    }
  };
  blob({3.1, 0.0, 5.0});  // 0.6 m beyond the crown's edge: joins it
  blob({6.0, 0.0, 5.0});  // 3.5 m away: no tree
  blob({1.5, 1.5, 0.5});  // under the crown, but low: understorey
  const Segmentation seg = segment_trees(cloud, ground, stems);
  std::size_t in_tree = 0;
  for (std::size_t p = 0; p < tree_points; ++p) in_tree += seg.tree[p] == 1;
  EXPECT_GT(in_tree, tree_points * 99 / 100);
  for (std::size_t p = tree_points; p < tree_points + 50; ++p) EXPECT_EQ(seg.tree[p], 1u) << p;
  for (std::size_t p = tree_points + 50; p < cloud.size(); ++p) EXPECT_EQ(seg.tree[p], 0u) << p;
  EXPECT_GE(seg.unassigned_points, 100u);
}

TEST(DescribeTrees, HeightAndCrownBase) {
  std::vector<Stem> stems;
  Ground ground;
  const PointCloud cloud = tree_with_crown(stems, ground);
  const Segmentation seg = segment_trees(cloud, ground, stems);
  const std::vector<TreeShape> shapes = describe_trees(cloud, stems, seg);
  ASSERT_EQ(shapes.size(), 1u);
  EXPECT_NEAR(shapes[0].height, 6.0, 0.01);
  EXPECT_NEAR(shapes[0].crown_base, 4.0, 0.26);
  EXPECT_EQ(shapes[0].points, static_cast<std::size_t>(std::count(seg.tree.begin(), seg.tree.end(), 1u)));
}

}  // namespace
}  // namespace treeskel::forest
