#include "treeskel/smooth.h"

#include "treeskel/error.h"

#include <gtest/gtest.h>

namespace treeskel {
namespace {

Skeleton fork() {
  Skeleton s;
  const Eigen::Vector3d at[] = {{0, 0, 0}, {0, 0, 1}, {0, 0, 2}, {-1, 0, 3}, {1, 0, 3}};
  for (int i = 0; i < 5; ++i) {
    SkeletonNode n;
    n.position = at[i];
    n.radius = 1.0 - 0.1 * i;
    n.points = {static_cast<std::uint32_t>(i)};
    add_node(s, n);
  }
  boost::add_edge(0, 1, s.graph);
  boost::add_edge(1, 2, s.graph);
  boost::add_edge(2, 3, s.graph);
  boost::add_edge(2, 4, s.graph);
  return s;
}

TEST(Smooth, InsertsSamplesBetweenEveryPairOfNodes) {
  const Skeleton s = fork();
  const Skeleton out = smooth_skeleton(s, {});
  EXPECT_EQ(out.node_count(), 5u + 4u * 5u);
  EXPECT_TRUE(is_tree(out.graph));
  EXPECT_EQ(count_branch_points(out.graph), 1u);
  EXPECT_EQ(count_endpoints(out.graph), 3u);
  EXPECT_EQ(validate(out, 5), "");
  for (NodeId v = 0; v < 5; ++v) {  // the original nodes are kept as they were
    EXPECT_EQ(out[v].position, s[v].position);
    EXPECT_EQ(out[v].points, s[v].points);
  }
  for (NodeId v = 5; v < out.node_count(); ++v) EXPECT_TRUE(out[v].points.empty());
}

TEST(Smooth, StraightChainStaysOnItsLineWithEvenSpacing) {
  Skeleton s;
  for (int i = 0; i < 4; ++i) {
    SkeletonNode n;
    n.position = {0, 0, double(i)};
    n.radius = 1.0;
    add_node(s, n);
    if (i) boost::add_edge(i - 1, i, s.graph);
  }
  const Skeleton out = smooth_skeleton(s, {});
  for (NodeId v = 0; v < out.node_count(); ++v) {
    EXPECT_NEAR(out[v].position.head<2>().norm(), 0.0, 1e-12);
    EXPECT_DOUBLE_EQ(out[v].radius, 1.0);
  }
  // Between nodes 1 and 2 the samples are at 1 + k/6 (a cardinal spline through evenly spaced points).
  const auto order = bfs_order(out.graph, 0);
  std::vector<double> z;
  for (auto v : order) z.push_back(out[v].position.z());
  for (std::size_t i = 0; i < z.size(); ++i) EXPECT_NEAR(z[i], i / 6.0, 1e-12);
}

TEST(Smooth, RadiiAreInterpolatedAndOptionsChecked) {
  const Skeleton out = smooth_skeleton(fork(), {1, 1.0});
  EXPECT_EQ(out.node_count(), 9u);
  for (NodeId v = 5; v < 9; ++v) {
    const auto nb = boost::adjacent_vertices(v, out.graph);
    const NodeId a = *nb.first, b = *std::next(nb.first);
    EXPECT_DOUBLE_EQ(out[v].radius, 0.5 * (out[a].radius + out[b].radius));
    EXPECT_TRUE(out[v].position.isApprox(0.5 * (out[a].position + out[b].position)));  // tension 1: straight
  }
  EXPECT_THROW(smooth_skeleton(fork(), {-1, 0.0}), OptionError);
  EXPECT_THROW(smooth_skeleton(fork(), {5, 1.5}), OptionError);
}

}  // namespace
}  // namespace treeskel
