#include "treeskel/skeleton.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <vector>

namespace treeskel {
namespace {

/// 0 - 1 - 2, and 1 - 3 - 4: one branch point (1), three endpoints (0, 2, 4).
Skeleton small_tree() {
  Skeleton s;
  for (int i = 0; i < 5; ++i) {
    SkeletonNode n;
    n.position = Eigen::Vector3d(i, 0, 0);
    n.points = {static_cast<std::uint32_t>(i)};
    add_node(s, n);
  }
  boost::add_edge(0, 1, s.graph);
  boost::add_edge(1, 2, s.graph);
  boost::add_edge(1, 3, s.graph);
  boost::add_edge(3, 4, s.graph);
  return s;
}

TEST(Skeleton, MovesTakeTheGraphWithoutCopyingIt) {
  Skeleton a = small_tree();
  a.root = 3;
  a.offset = Eigen::Vector3d(1, 2, 3);
  a.noise_points = {7, 9};
  a.left_out.outliers = 2;
  const Skeleton copy = a;
  const SkeletonNode* node = &a[2];
  const std::uint32_t* points = a[2].points.data();

  Skeleton b(std::move(a));
  EXPECT_EQ(&b[2], node);  // the very nodes, not copies
  EXPECT_EQ(b[2].points.data(), points);
  EXPECT_EQ(b.node_count(), copy.node_count());
  EXPECT_EQ(b.edge_count(), copy.edge_count());
  EXPECT_EQ(b.root, 3u);
  EXPECT_EQ(b.offset, copy.offset);
  EXPECT_EQ(b.noise_points, copy.noise_points);
  EXPECT_EQ(b.left_out.outliers, 2u);
  EXPECT_TRUE(is_tree(b.graph));
  EXPECT_EQ(count_branch_points(b.graph), 1u);
  EXPECT_EQ(a.node_count(), 0u);  // NOLINT(bugprone-use-after-move): moved from, left empty
  EXPECT_TRUE(a.noise_points.empty());

  Skeleton c = small_tree();
  c = std::move(b);
  EXPECT_EQ(&c[2], node);
  EXPECT_EQ(c.root, 3u);
  EXPECT_EQ(c.noise_points, copy.noise_points);
  EXPECT_EQ(count_endpoints(c.graph), 3u);
  EXPECT_EQ(b.node_count(), 0u);  // NOLINT(bugprone-use-after-move)
  // The edges still name the right nodes: adding to the moved graph works.
  const NodeId extra = add_node(c, SkeletonNode{});
  boost::add_edge(extra, 4, c.graph);
  EXPECT_TRUE(is_tree(c.graph));
  EXPECT_EQ(count_endpoints(c.graph), 3u);
}

TEST(Skeleton, RecentreOffsetKeepsTheWorldPositions) {
  Skeleton s = small_tree();
  s.offset = Eigen::Vector3d(600000.0, 5200000.0, 100.0);
  s[2].position.y() = -3.0;
  s[4].position.z() = 2.0;
  std::vector<Eigen::Vector3d> world;
  for (NodeId v = 0; v < s.node_count(); ++v) world.push_back(s[v].position + s.offset);
  recentre_offset(s);
  EXPECT_EQ(s.offset, Eigen::Vector3d(600000.0, 5199997.0, 100.0));
  Eigen::AlignedBox3d box;
  for (NodeId v = 0; v < s.node_count(); ++v) {
    EXPECT_EQ(s[v].position + s.offset, world[v]) << v;
    box.extend(s[v].position);
  }
  EXPECT_EQ(box.min(), Eigen::Vector3d::Zero());
  Skeleton empty;
  recentre_offset(empty);
  EXPECT_EQ(empty.offset, Eigen::Vector3d::Zero());
}

TEST(Skeleton, CountsBranchPointsAndEndpoints) {
  const Skeleton s = small_tree();
  EXPECT_EQ(count_branch_points(s.graph), 1u);
  EXPECT_EQ(count_endpoints(s.graph), 3u);
  EXPECT_TRUE(is_tree(s.graph));
  EXPECT_DOUBLE_EQ(total_length(s.graph), 1.0 + 1.0 + 2.0 + 1.0);
}

TEST(Skeleton, DetectsCyclesAndSplits) {
  Skeleton cycle = small_tree();
  boost::add_edge(2, 4, cycle.graph);
  EXPECT_FALSE(is_tree(cycle.graph));
  EXPECT_EQ(validate(cycle, 5), "the skeleton has a cycle");

  Skeleton split = small_tree();
  boost::remove_edge(1, 3, split.graph);
  EXPECT_EQ(count_components(split.graph), 2u);
  EXPECT_EQ(validate(split, 5), "the skeleton is not connected");

  Skeleton loop = small_tree();
  boost::remove_edge(3, 4, loop.graph);
  boost::add_edge(4, 4, loop.graph);
  EXPECT_FALSE(is_tree(loop.graph));
}

TEST(Skeleton, ValidateChecksPointOwnership) {
  Skeleton s = small_tree();
  EXPECT_EQ(validate(s, 5), "");
  EXPECT_EQ(validate(s, 6), "point 5 is claimed 0 times");
  s.noise_points = {5};
  EXPECT_EQ(validate(s, 6), "");
  s[0].points.push_back(2);
  EXPECT_EQ(validate(s, 6), "point 2 is claimed 2 times");
}

TEST(Skeleton, ParentsAndOrderFromRoot) {
  const Skeleton s = small_tree();
  const auto parent = parents_from_root(s.graph, 0);
  EXPECT_EQ(parent, (std::vector<NodeId>{0, 0, 1, 1, 3}));
  const auto order = bfs_order(s.graph, 4);
  EXPECT_EQ(order.front(), 4u);
  EXPECT_EQ(order.size(), 5u);
}

TEST(Skeleton, CompactKeepsEdgesBetweenKeptNodes) {
  Skeleton s = small_tree();
  s.root = 4;
  const auto remap = compact_nodes(s, {true, true, false, true, true});
  EXPECT_EQ(remap, (std::vector<std::int64_t>{0, 1, -1, 2, 3}));
  EXPECT_EQ(s.node_count(), 4u);
  EXPECT_EQ(s.edge_count(), 3u);
  EXPECT_EQ(s.root, 3u);
  EXPECT_EQ(s[2].position, Eigen::Vector3d(3, 0, 0));
  EXPECT_TRUE(is_tree(s.graph));
}

}  // namespace
}  // namespace treeskel
