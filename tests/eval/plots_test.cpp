// Synthetic plots: deterministic, every kind of point present, the truth consistent; and the scores
// of a segmentation on a case small enough to count by hand.
#include "treeskel/eval/plots.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace treeskel::eval {
namespace {

PlotOptions tiny() {
  PlotOptions o;
  o.trees = 3;
  o.width = 8.0;
  o.shrubs = 2;
  o.points_per_tree = 3000;
  o.ground_density = 5;
  return o;
}

TEST(MakePlot, DeterministicWithEveryKindAndTheTruthPerPoint) {
  const SyntheticPlot a = make_plot(tiny()), b = make_plot(tiny());
  ASSERT_EQ(a.cloud.positions, b.cloud.positions);
  EXPECT_EQ(a.tree, b.tree);
  ASSERT_EQ(a.stems.size(), 3u);
  ASSERT_EQ(a.tree.size(), a.cloud.size());
  ASSERT_EQ(a.kind.size(), a.cloud.size());
  for (auto k : {PointKind::ground, PointKind::wood, PointKind::leaf, PointKind::understorey})
    EXPECT_NE(std::find(a.kind.begin(), a.kind.end(), k), a.kind.end()) << static_cast<int>(k);
  for (std::size_t p = 0; p < a.cloud.size(); ++p) {
    const bool in_tree = a.kind[p] == PointKind::wood || a.kind[p] == PointKind::leaf;
    ASSERT_EQ(a.tree[p] != 0, in_tree) << p;
    ASSERT_LE(a.tree[p], a.stems.size());
  }
  // Stems at least the spacing apart; another seed, another plot.
  for (std::size_t i = 0; i < a.stems.size(); ++i)
    for (std::size_t j = i + 1; j < a.stems.size(); ++j)
      EXPECT_GE((a.stems[i] - a.stems[j]).head<2>().norm(), tiny().min_spacing);
  PlotOptions other = tiny();
  other.seed = 2;
  EXPECT_NE(make_plot(other).stems[0], a.stems[0]);
}

TEST(ScorePlot, CountsByHand) {
  SyntheticPlot plot;
  plot.stems = {{0, 0, 0}, {10, 0, 0}};
  // True tree 1: points 0-3; true tree 2: points 4-5; ground: point 6.
  plot.tree = {1, 1, 1, 1, 2, 2, 0};
  plot.kind = {PointKind::wood, PointKind::wood, PointKind::leaf, PointKind::leaf, PointKind::wood, PointKind::wood,
               PointKind::ground};
  plot.cloud.positions.resize(7, Eigen::Vector3d::Zero());
  // Found: a stem 0.3 from tree 1, one far from everything; tree 2 not found.
  const std::vector<Eigen::Vector2d> found{{0.3, 0.0}, {5.0, 5.0}};
  const std::vector<std::uint32_t> labels{1, 1, 1, 2, 1, 0, 1};
  const PlotScore s = score_plot(plot, found, labels);
  EXPECT_EQ(s.matched_stems, 1u);
  EXPECT_DOUBLE_EQ(s.stem_precision, 0.5);
  EXPECT_DOUBLE_EQ(s.stem_recall, 0.5);
  // Tree 1 and found 1: 3 in both, union 4 + 5 - 3 = 6; tree 2 unmatched counts 0.
  EXPECT_DOUBLE_EQ(s.mean_iou, (3.0 / 6.0 + 0.0) / 2.0);
  EXPECT_DOUBLE_EQ(s.tree_points_elsewhere, 2.0 / 6.0);
  EXPECT_DOUBLE_EQ(s.tree_points_unassigned, 1.0 / 6.0);
  EXPECT_DOUBLE_EQ(s.others_in_trees, 1.0);
}

}  // namespace
}  // namespace treeskel::eval
