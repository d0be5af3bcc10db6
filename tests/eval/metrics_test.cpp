#include "treeskel/eval/metrics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

namespace treeskel::eval {
namespace {

/// A Y: root (0,0,0) - fork (0,0,1) - tips (±1,0,2), optionally shifted.
Skeleton y_shape(const Eigen::Vector3d& shift = Eigen::Vector3d::Zero()) {
  Skeleton s;
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 0, 2),
                                   Eigen::Vector3d(-1, 0, 2)}) {
    SkeletonNode n;
    n.position = p + shift;
    add_node(s, n);
  }
  boost::add_edge(0, 1, s.graph);
  boost::add_edge(1, 2, s.graph);
  boost::add_edge(1, 3, s.graph);
  return s;
}

TEST(Metrics, IdenticalSkeletonsScorePerfectly) {
  const Metrics m = evaluate(y_shape(), y_shape());
  EXPECT_EQ(m.spd, 0.0);
  EXPECT_EQ(m.reverse_spd, 0.0);
  EXPECT_EQ(m.bpc, 1.0);
  EXPECT_EQ(m.epc, 1.0);
  EXPECT_EQ(m.bp_precision, 1.0);
  EXPECT_EQ(m.ep_precision, 1.0);
  EXPECT_EQ(m.components, 1u);
  EXPECT_EQ(m.cycles, 0u);
}

TEST(Metrics, HandComputedShift) {
  // Shifted by 0.03 across every edge's plane: each truth node is 0.03 from the predicted edges.
  const Metrics m = evaluate(y_shape({0, 0.03, 0}), y_shape());
  EXPECT_NEAR(m.spd, 0.03, 1e-12);
  EXPECT_NEAR(m.reverse_spd, 0.03, 1e-12);
  EXPECT_EQ(m.bpc, 1.0);
  const Metrics far = evaluate(y_shape({0, 0.06, 0}), y_shape());
  EXPECT_EQ(far.bpc, 0.0);
  EXPECT_EQ(far.epc, 0.0);
}

TEST(Metrics, TauIsAStrictBound) {
  // The paper covers a point only if its distance is less than τ.
  const std::vector<Eigen::Vector3d> truth{{0, 0, 0}};
  EXPECT_EQ(matched_within(truth, {{0.05, 0, 0}}, 0.05), 0u);
  EXPECT_EQ(matched_within(truth, {{0.0499999, 0, 0}}, 0.05), 1u);
}

TEST(Metrics, SpuriousBranchesShowInPrecisionNotRecall) {
  Skeleton extra = y_shape();
  SkeletonNode n;
  n.position = {0.5, 0, 0.5};
  const NodeId v = add_node(extra, n);
  SkeletonNode m2;
  m2.position = {0, 0, 0.5};
  const NodeId w = add_node(extra, m2);
  boost::remove_edge(0, 1, extra.graph);
  boost::add_edge(0, w, extra.graph);
  boost::add_edge(w, 1, extra.graph);
  boost::add_edge(w, v, extra.graph);  // a side twig at mid-trunk
  const Metrics m = evaluate(extra, y_shape());
  EXPECT_EQ(m.bpc, 1.0);
  EXPECT_EQ(m.epc, 1.0);
  EXPECT_DOUBLE_EQ(m.bp_precision, 0.5);
  EXPECT_DOUBLE_EQ(m.ep_precision, 0.75);
  EXPECT_GT(m.reverse_spd, 0.0);
}

TEST(Metrics, CountsCyclesAndComponents) {
  Skeleton s = y_shape();
  boost::add_edge(2, 3, s.graph);
  SkeletonNode lone;
  add_node(s, lone);
  const Metrics m = evaluate(s, y_shape());
  EXPECT_EQ(m.cycles, 1u);
  EXPECT_EQ(m.components, 2u);
}

TEST(Hungarian, MatchesBruteForceOnRandomMatrices) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0.0, 10.0);
  for (int trial = 0; trial < 200; ++trial) {
    const int rows = 1 + trial % 6, cols = 1 + (trial / 6) % 6;
    Eigen::MatrixXd cost(rows, cols);
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) cost(r, c) = u(rng);
    const auto assignment = min_cost_assignment(cost);
    double got = 0.0;
    std::vector<bool> used(cols, false);
    int assigned = 0;
    for (int r = 0; r < rows; ++r) {
      if (assignment[r] < 0) continue;
      ASSERT_FALSE(used[assignment[r]]);
      used[assignment[r]] = true;
      got += cost(r, assignment[r]);
      ++assigned;
    }
    ASSERT_EQ(assigned, std::min(rows, cols));
    // Brute force over the permutations of the larger side.
    const int k = std::max(rows, cols);
    std::vector<int> perm(k);
    std::iota(perm.begin(), perm.end(), 0);
    double best = 1e300;
    do {
      double sum = 0.0;
      for (int i = 0; i < std::min(rows, cols); ++i) sum += rows <= cols ? cost(i, perm[i]) : cost(perm[i], i);
      best = std::min(best, sum);
    } while (std::next_permutation(perm.begin(), perm.end()));
    EXPECT_NEAR(got, best, 1e-9) << rows << "x" << cols;
  }
}

}  // namespace
}  // namespace treeskel::eval
