#include "treeskel/junction.h"

#include <gtest/gtest.h>

#include <cmath>

namespace treeskel {
namespace {

/// A Y: a trunk along z (nodes every 0.1 up to 0.9), two arms at +-30 degrees from the true junction
/// (0, 0, 1) with nodes from `first_t` along them, and the fork node at `fork`, joined to the trunk's
/// top and to each arm's first node. Every node owns one point, its own index.
Skeleton y_with_fork_at(const Eigen::Vector3d& fork, double first_t) {
  Skeleton s;
  auto node = [&](const Eigen::Vector3d& p) {
    SkeletonNode n;
    n.position = p;
    n.radius = 0.05;
    n.points = {static_cast<std::uint32_t>(s.node_count())};
    return add_node(s, n);
  };
  NodeId below = node({0, 0, 0});
  for (int i = 1; i <= 9; ++i) {
    const NodeId v = node({0, 0, 0.1 * i});
    boost::add_edge(below, v, s.graph);
    below = v;
  }
  const NodeId f = node(fork);
  boost::add_edge(below, f, s.graph);
  for (const double side : {-1.0, 1.0}) {
    const Eigen::Vector3d d(side * std::sin(M_PI / 6), 0, std::cos(M_PI / 6));
    NodeId previous = f;
    for (double t = first_t; t < 1.2; t += 0.1) {
      const NodeId v = node(Eigen::Vector3d(0, 0, 1) + t * d);
      boost::add_edge(previous, v, s.graph);
      previous = v;
    }
  }
  s.root = 0;
  return s;
}

std::size_t owned_points(const Skeleton& s) {
  std::size_t n = 0;
  for (NodeId v = 0; v < s.node_count(); ++v) n += s[v].points.size();
  return n;
}

NodeId the_fork(const Skeleton& s) {
  for (NodeId v = 0; v < s.node_count(); ++v)
    if (boost::degree(v, s.graph) == 3) return v;
  return s.node_count();
}

TEST(RelocateForks, MovesAForkToWhereTheArmAxesMeet) {
  Skeleton s = y_with_fork_at({0, 0, 1.15}, 0.3);  // level sets put it where the surfaces part
  const std::size_t nodes = s.node_count(), points = owned_points(s);
  JunctionOptions o;
  o.arm_length = 0.6;
  EXPECT_EQ(relocate_forks(s, 0.05, o), 1u);
  const NodeId f = the_fork(s);
  ASSERT_LT(f, s.node_count());
  EXPECT_LT((s[f].position - Eigen::Vector3d(0, 0, 1)).norm(), 0.02) << s[f].position.transpose();
  EXPECT_EQ(s.node_count(), nodes);  // nothing on the wrong side
  EXPECT_EQ(owned_points(s), points);
  EXPECT_TRUE(is_tree(s.graph));
}

TEST(RelocateForks, NodesLeftOnTheWrongSideJoinTheFork) {
  // The fork sits below the junction; the arms' first nodes are 0.02 past it, so once the fork moves
  // up they are behind it and merge into it, handing it their points.
  Skeleton s = y_with_fork_at({0, 0, 0.95}, 0.02);
  const std::size_t nodes = s.node_count(), points = owned_points(s);
  JunctionOptions o;
  o.arm_length = 0.6;
  o.max_move_radii = 10.0;
  EXPECT_EQ(relocate_forks(s, 0.05, o), 1u);
  EXPECT_EQ(s.node_count(), nodes - 2);
  EXPECT_EQ(owned_points(s), points);
  EXPECT_TRUE(is_tree(s.graph));
  const NodeId f = the_fork(s);
  ASSERT_LT(f, s.node_count());
  EXPECT_EQ(s[f].points.size(), 3u);
  EXPECT_LT((s[f].position - Eigen::Vector3d(0, 0, 1)).norm(), 0.03) << s[f].position.transpose();
}

TEST(RelocateForks, AMoveBeyondTheLimitIsNotMade) {
  Skeleton s = y_with_fork_at({0, 0, 1.15}, 0.3);
  const Eigen::Vector3d before = s[10].position;
  JunctionOptions o;
  o.arm_length = 0.6;
  o.max_move_radii = 0.5;  // 0.025 + one band (0.05): less than the 0.15 the fork would move
  EXPECT_EQ(relocate_forks(s, 0.05, o), 0u);
  EXPECT_EQ(s[10].position, before);
}

TEST(RelocateForks, AChainWithoutForksIsLeftAlone) {
  Skeleton s;
  for (int i = 0; i < 6; ++i) {
    SkeletonNode n;
    n.position = {0.01 * i * i, 0, 0.1 * i};
    n.radius = 0.05;
    add_node(s, n);
    if (i > 0) boost::add_edge(i - 1, i, s.graph);
  }
  const Skeleton before = s;
  EXPECT_EQ(relocate_forks(s, 0.05), 0u);
  for (NodeId v = 0; v < s.node_count(); ++v) EXPECT_EQ(s[v].position, before[v].position);
}

}  // namespace
}  // namespace treeskel
