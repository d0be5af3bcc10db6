// A quality regression guard: a few of the benchmark's clouds (seed 1), skeletonized with the default
// options, must keep scoring about what they scored when the thresholds were set (measured values
// less a margin; the full benchmark is bench/accuracy.cpp). It catches a stage that breaks.
#include "treeskel/eval/hard_trees.h"
#include "treeskel/eval/metrics.h"
#include "treeskel/eval/paper_trees.h"
#include "treeskel/pipeline.h"

#include <gtest/gtest.h>

namespace treeskel::eval {
namespace {

struct Expectation {
  const char* cloud;
  double max_spd, min_bpc, min_epc, min_bp_precision, min_ep_precision;
};

void expect_scores(const Metrics& m, const Expectation& e) {
  EXPECT_LE(m.spd, e.max_spd);
  EXPECT_GE(m.bpc, e.min_bpc);
  EXPECT_GE(m.epc, e.min_epc);
  EXPECT_GE(m.bp_precision, e.min_bp_precision);
  EXPECT_GE(m.ep_precision, e.min_ep_precision);
}

class AccuracyRegression : public ::testing::TestWithParam<Expectation> {};

TEST_P(AccuracyRegression, KeepsItsScores) {
  const Expectation& e = GetParam();
  const int tree = e.cloud[4] - '0';
  const GroundTruth truth = make_paper_tree(tree, 1);
  for (auto& c : make_paper_clouds(truth, tree, 1)) {
    if (c.name != e.cloud) continue;
    recentre_offset(c.cloud);
    const Skeleton s = extract_skeleton(c.cloud);
    EXPECT_EQ(validate(s, c.cloud.size()), "");
    const Metrics m = evaluate(s, truth.skeleton);
    expect_scores(m, e);
    return;
  }
  FAIL() << "no cloud named " << e.cloud;
}

// Measured when set (defaults of 2 points a cell and spur pruning within 1.75 radii): tree2_16647 SPD
// 0.0010, BPC/EPC/precisions 1.0; tree1_noise_2 0.0024, 1.0, 1.0, 0.79, 0.76; tree4_missing_1 0.0034,
// 0.94, 0.94, 0.90, 0.98; tree3_vdensity_1 0.0019, 1.0, 1.0, 0.96, 0.96. tree2_missing_2, whose
// occlusion cuts the crown into pieces nearer one another than the tree (bridging in rounds, 5
// December 2026): 0.0035, 0.909, 0.923, 0.769, 0.800 (SPD 0.145 and BPC 0.273 with one round).
// tree6_missing_2, a piece of 1,848 cells whose probes lay deep inside it until they were taken
// from its rim (the same day): 0.0030, 0.983, 0.966, 0.781, 0.915 (SPD 0.075, BPC 0.621 before).
INSTANTIATE_TEST_SUITE_P(Benchmark, AccuracyRegression,
                         ::testing::Values(Expectation{"tree2_16647", 0.003, 0.9, 0.9, 0.9, 0.9},
                                           Expectation{"tree1_noise_2", 0.005, 0.9, 0.9, 0.7, 0.65},
                                           Expectation{"tree4_missing_1", 0.007, 0.85, 0.85, 0.8, 0.85},
                                           Expectation{"tree3_vdensity_1", 0.004, 0.9, 0.9, 0.85, 0.85},
                                           Expectation{"tree2_missing_2", 0.01, 0.8, 0.8, 0.65, 0.7},
                                           Expectation{"tree6_missing_2", 0.01, 0.9, 0.9, 0.7, 0.85}),
                         [](const auto& info) { return std::string(info.param.cloud); });

// The harder sets of eval/hard_trees.h (seed 1): today's scores less a margin, so that work on crowded
// crowns and sparse scans (issue: they are far below the paper set) can only raise them. Measured when
// set: crowded6_44003 SPD 0.003, BPC 0.845, EPC 0.730, precisions 0.875 / 1.0; sparse60_2views_4113
// 0.004, 0.917, 0.927, 0.743, 0.894; tree4_all 0.009, 0.877, 0.851, 0.814, 0.860. With cell sizes
// between two depths (OctreeOptions::depth_steps): crowded5_23011 0.004, 0.473, 0.390, 0.981, 1.0
// (0.236 and 0.227 with whole depths); tree4_all 0.005, 0.892, 0.839, 0.744, 0.811. With bridging in
// rounds: sparse60_1view_5793 0.008, 0.745, 0.720, 0.804, 0.900 (SPD 0.074, BPC 0.564 with one).
// With leaves kept from half a band (PruneOptions::min_bands) and the truth cut by each branch's own
// points (CutOptions::own_points): sparse130_2views_6066 0.004, 0.936, 0.831, 0.801, 0.873 (0.920,
// 0.813, 0.804, 0.871 with a whole band; against the truth cut by any points, 0.923, 0.823, 0.822,
// 0.911); sparse60_1view_5793 0.008, 0.765, 0.838, 0.750, 0.934; sparse60_2views_4113 0.004, 0.950,
// 0.963, 0.740, 0.898. With spurs at close forks removed (PruneOptions::close_forks):
// sparse130_2views_6066 0.004, 0.912, 0.789, 0.832, 0.897; tree4_all 0.004, 0.938, 0.931, 0.772,
// 0.890 (precisions 0.753 and 0.871 without). With spurs judged with their host's points
// (PruneOptions::point_host_factor): sparse60_2views_4113 0.004, 0.983, 0.878, 0.855, 0.911 (0.950,
// 0.866, 0.851, 0.922 on the nodes' radii alone); sparse130_2views_6066 0.004, 0.920, 0.789, 0.852,
// 0.910; sparse60_1view_5793 0.008, 0.765, 0.824, 0.750, 0.918 (0.824, 0.794, 0.857, 0.931);
// crowded5_23011 0.004, 0.455, 0.364, 0.980, 1.0 (0.464, 0.383); tree4_all 0.004, 0.938, 0.931,
// 0.782, 0.900.
class HardAccuracyRegression : public ::testing::TestWithParam<Expectation> {};

TEST_P(HardAccuracyRegression, KeepsItsScores) {
  const Expectation& e = GetParam();
  const std::string name = e.cloud;
  const auto clouds = name.rfind("crowded", 0) == 0  ? make_crowded_clouds(1)
                      : name.rfind("sparse", 0) == 0 ? make_sparse_clouds(1)
                                                     : make_combined_clouds(1);
  for (auto c : clouds) {
    if (c.name != name) continue;
    recentre_offset(c.cloud);
    const Skeleton s = extract_skeleton(c.cloud);
    EXPECT_EQ(validate(s, c.cloud.size()), "");
    const Metrics m = evaluate(s, c.truth.skeleton);
    expect_scores(m, e);
    return;
  }
  FAIL() << "no cloud named " << name;
}

INSTANTIATE_TEST_SUITE_P(HarderSets, HardAccuracyRegression,
                         ::testing::Values(Expectation{"crowded6_44003", 0.006, 0.78, 0.66, 0.8, 0.9},
                                           Expectation{"crowded5_23011", 0.006, 0.42, 0.34, 0.9, 0.9},
                                           Expectation{"sparse60_2views_4113", 0.008, 0.93, 0.85, 0.82, 0.88},
                                           Expectation{"sparse60_1view_5793", 0.02, 0.65, 0.65, 0.7, 0.8},
                                           Expectation{"sparse130_2views_6066", 0.008, 0.89, 0.77, 0.83, 0.89},
                                           Expectation{"tree4_all", 0.014, 0.8, 0.78, 0.76, 0.88}),
                         [](const auto& info) { return std::string(info.param.cloud); });

}  // namespace
}  // namespace treeskel::eval
