#include "treeskel/complete.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace treeskel {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// A vertical trunk from z = 0 to 2 as a skeleton of 21 nodes of radius `radius`, with the points of
/// its bark (rings every 0.02, 24 points each, seeded noise) shared among its nodes by height.
struct Trunk {
  PointCloud cloud;
  Skeleton skeleton;
  std::size_t bark = 0;  ///< points of the bark, first in the cloud
};

Trunk trunk(double radius) {
  Trunk t;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> noise(-0.002, 0.002);
  for (int ring = 0; ring <= 100; ++ring)
    for (int k = 0; k < 24; ++k) {
      const double a = 2.0 * kPi * k / 24.0;
      t.cloud.positions.emplace_back(radius * std::cos(a) + noise(random), radius * std::sin(a) + noise(random), 0.02 * ring);
    }
  t.bark = t.cloud.size();
  for (int i = 0; i <= 20; ++i) {
    SkeletonNode node;
    node.position = {0.0, 0.0, 0.1 * i};
    node.radius = radius;
    add_node(t.skeleton, node);
    if (i > 0) boost::add_edge(static_cast<NodeId>(i - 1), static_cast<NodeId>(i), t.skeleton.graph);
  }
  return t;
}

/// Gives every point of `cloud` from `first` on to the skeleton node nearest to it.
void share_points(Trunk& t, std::size_t first) {
  for (std::size_t p = first; p < t.cloud.size(); ++p) {
    NodeId best = 0;
    for (NodeId v = 1; v < t.skeleton.node_count(); ++v)
      if ((t.skeleton[v].position - t.cloud.positions[p]).norm() < (t.skeleton[best].position - t.cloud.positions[p]).norm())
        best = v;
    t.skeleton[best].points.push_back(static_cast<std::uint32_t>(p));
  }
}

/// Every node of `before` still holds the points it held (nothing was grafted from them).
void expect_same_points(const Skeleton& before, const Skeleton& after) {
  for (NodeId v = 0; v < before.node_count(); ++v) EXPECT_EQ(after[v].points, before[v].points) << "node " << v;
}

/// Adds the points of a twig: from `from` to `to`, one every `step`, each with a seeded jitter.
void add_twig(PointCloud& cloud, const Eigen::Vector3d& from, const Eigen::Vector3d& to, double step) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> jitter(-0.003, 0.003);
  const int count = static_cast<int>(std::round((to - from).norm() / step));
  for (int i = 0; i <= count; ++i)
    cloud.positions.push_back(from + (to - from) * (static_cast<double>(i) / count) +
                              Eigen::Vector3d(jitter(random), jitter(random), jitter(random)));
}

// A twig the skeleton passed by (its points were given to the trunk's nodes) becomes a branch of its
// own that reaches its tip, hangs from the trunk where it leaves it, and holds the points that lay
// outside the trunk; the bark stays with the trunk, and the skeleton stays one tree.
TEST(Complete, GrowsABranchThroughATwigTheSkeletonPassedBy) {
  Trunk t = trunk(0.05);
  add_twig(t.cloud, {0.05, 0, 1.0}, {0.6, 0, 1.3}, 0.02);
  share_points(t, 0);
  const std::size_t n = t.cloud.size();
  const CompleteStats stats = complete_skeleton(t.skeleton, t.cloud, 0.03);
  EXPECT_EQ(validate(t.skeleton, n), "");
  EXPECT_TRUE(is_tree(t.skeleton.graph));
  EXPECT_EQ(stats.branches, 1u);
  EXPECT_EQ(stats.nodes, t.skeleton.node_count() - 21);
  EXPECT_GE(stats.nodes, 8u);  // a node per two cells of path length along a twig 0.63 long
  std::size_t tips = 0;  // one chain, not two interleaved ones
  for (NodeId v = 21; v < t.skeleton.node_count(); ++v) tips += boost::degree(v, t.skeleton.graph) == 1;
  EXPECT_EQ(tips, 1u);
  // Every twig point more than a cell outside the trunk (0.05 + 0.03 from the axis) is held by a new
  // node, with at most the first one (its path alone in the first band: a tuft too small to graft).
  EXPECT_LE(stats.grafted_points, stats.uncovered_points);
  EXPECT_GE(stats.grafted_points + 1, stats.uncovered_points);
  for (NodeId v = 0; v < t.skeleton.node_count(); ++v)
    for (auto p : t.skeleton[v].points) {
      if (v < 21) EXPECT_LT(t.cloud.positions[p].x(), 0.09) << p;  // the bark and the twig's base
      else EXPECT_GT(t.cloud.positions[p].x(), 0.08) << p;
    }
  // The farthest new node is at the tip, and the branch leaves the trunk near z = 1.
  double reach = 0.0;
  NodeId base = 0;
  for (NodeId v = 21; v < t.skeleton.node_count(); ++v) {
    reach = std::max(reach, t.skeleton[v].position.x());
    for (auto [a, end] = boost::adjacent_vertices(v, t.skeleton.graph); a != end; ++a)
      if (*a < 21) base = *a;
  }
  EXPECT_NEAR(reach, 0.6, 0.02);
  EXPECT_NEAR(t.skeleton[base].position.z(), 1.0, 0.11);
}

// A thick trunk's bark lies a radius from the axis, and is covered: nothing changes.
TEST(Complete, LeavesPointsWithinTheRadiusAlone) {
  Trunk t = trunk(0.3);
  share_points(t, 0);
  const Skeleton before = t.skeleton;
  const CompleteStats stats = complete_skeleton(t.skeleton, t.cloud, 0.03);
  EXPECT_EQ(stats.uncovered_points, 0u);
  EXPECT_EQ(stats.nodes, 0u);
  EXPECT_EQ(t.skeleton.node_count(), before.node_count());
  expect_same_points(before, t.skeleton);
}

// A tuft of fewer points than `min_points` is no branch: its points stay with the node that held
// them, and points with no path to the covered ones (farther than `link`) stay too.
TEST(Complete, LeavesSmallTuftsAndUnreachablePointsWhereTheyWere) {
  Trunk t = trunk(0.05);
  add_twig(t.cloud, {0.10, 0, 0.5}, {0.14, 0, 0.5}, 0.02);  // three points
  add_twig(t.cloud, {1.0, 0, 1.5}, {1.4, 0, 1.5}, 0.02);    // 21 points, 0.95 from the trunk
  share_points(t, 0);
  const Skeleton before = t.skeleton;
  const CompleteStats stats = complete_skeleton(t.skeleton, t.cloud, 0.03);
  EXPECT_EQ(stats.uncovered_points, 24u);
  EXPECT_EQ(stats.nodes, 0u);
  expect_same_points(before, t.skeleton);
  CompleteOptions fewer;
  fewer.min_points = 3;
  fewer.min_reach = 0.05;  // the tuft reaches 0.09 outside the tube: not past the default, three cells
  EXPECT_EQ(complete_skeleton(t.skeleton, t.cloud, 0.03, fewer).branches, 1u);
  EXPECT_EQ(validate(t.skeleton, t.cloud.size()), "");
}

// Noise on the bark: points scattered up to two cells outside the tube along the whole trunk. They
// are uncovered, and connected, but reach no farther than `min_reach` (three cells) outside the tube:
// tufts, not branches, so nothing is grafted (with a smaller `min_reach` they would be).
TEST(Complete, LeavesNoiseOnTheBarkAlone) {
  Trunk t = trunk(0.05);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> out(0.09, 0.11), turn(0.0, 2.0 * kPi), along(0.2, 1.8);
  for (int i = 0; i < 400; ++i) {
    const double r = out(random), a = turn(random);
    t.cloud.positions.emplace_back(r * std::cos(a), r * std::sin(a), along(random));
  }
  share_points(t, 0);
  const Skeleton before = t.skeleton;
  const CompleteStats stats = complete_skeleton(t.skeleton, t.cloud, 0.03);
  EXPECT_GE(stats.uncovered_points, 390u);
  EXPECT_EQ(stats.nodes, 0u);
  expect_same_points(before, t.skeleton);
  CompleteOptions tufts;
  tufts.min_reach = 0.035;
  tufts.max_branching = 0.0;
  Skeleton nearer = t.skeleton;
  EXPECT_GT(complete_skeleton(nearer, t.cloud, 0.03, tufts).nodes, 0u);
  // Asked to keep them (`--complete-all`), every group of enough points grows a twig; the skeleton
  // stays a tree that holds every point once.
  Skeleton all = t.skeleton;
  const CompleteStats grown = complete_skeleton(all, t.cloud, 0.03, all_grafts());
  EXPECT_GT(grown.nodes, 0u);
  EXPECT_GT(grown.grafted_points, 9 * grown.uncovered_points / 10);  // all but groups of under 4 points
  EXPECT_EQ(validate(all, t.cloud.size()), "");
  EXPECT_TRUE(is_tree(all.graph));
}

/// Adds a bush: a stalk from `from` along +x, and at its end `spurs` short twigs splaying out in
/// seeded random directions (like leaves, or noise, around the end of a twig).
void add_bush(PointCloud& cloud, const Eigen::Vector3d& from, int spurs) {
  const Eigen::Vector3d centre = from + Eigen::Vector3d(0.25, 0, 0);
  add_twig(cloud, from, centre, 0.02);
  std::mt19937 random(5);
  std::normal_distribution<double> gauss;
  for (int s = 0; s < spurs; ++s) {
    const Eigen::Vector3d d = Eigen::Vector3d(gauss(random), gauss(random), gauss(random)).normalized();
    add_twig(cloud, centre + 0.02 * d, centre + 0.15 * d, 0.02);
  }
}

// A graft that splays into many short spurs is a bush (leaves or noise around a twig), not a
// branch: with the default `max_branching` it is not added and its points stay where they were,
// while a twig beside it is grafted; with no limit, the bush is grafted too.
TEST(Complete, LeavesBushesOutAndGraftsTheTwigBesideThem) {
  Trunk t = trunk(0.05);
  add_twig(t.cloud, {-0.05, 0, 0.5}, {-0.6, 0, 0.8}, 0.02);
  const std::size_t bush = t.cloud.size();
  add_bush(t.cloud, {0.05, 0, 1.4}, 12);
  share_points(t, 0);
  Skeleton limited = t.skeleton;
  const CompleteStats stats = complete_skeleton(limited, t.cloud, 0.03);
  EXPECT_EQ(validate(limited, t.cloud.size()), "");
  EXPECT_EQ(stats.branches, 1u);
  EXPECT_EQ(stats.bushy_grafts, 1u);
  EXPECT_GE(stats.bushy_points + 4, t.cloud.size() - bush);  // all of the bush but a few points by the trunk
  EXPECT_EQ(stats.grafted_points + stats.bushy_points, stats.uncovered_points);  // nothing else is left
  for (NodeId v = 21; v < limited.node_count(); ++v)
    for (auto p : limited[v].points) EXPECT_LT(p, bush) << "a point of the bush is in a grafted node";

  CompleteOptions unlimited;
  unlimited.max_branching = 0.0;
  Skeleton grown = t.skeleton;
  const CompleteStats all = complete_skeleton(grown, t.cloud, 0.03, unlimited);
  EXPECT_EQ(all.branches, 2u);
  EXPECT_EQ(all.bushy_grafts, 0u);
  EXPECT_EQ(validate(grown, t.cloud.size()), "");
  EXPECT_TRUE(is_tree(grown.graph));

  // Keeping the tufts and bushes (`--complete-all`) grows the bush while bushes hold at most
  // `max_bush_share` of the cloud; past it the crown counts as leafy and the bush is left out.
  const double share = static_cast<double>(stats.bushy_points) / static_cast<double>(t.cloud.size());
  CompleteOptions everything = all_grafts();
  everything.max_bush_share = share + 0.02;
  Skeleton bushy = t.skeleton;
  const CompleteStats kept = complete_skeleton(bushy, t.cloud, 0.03, everything);
  EXPECT_FALSE(kept.leafy_bushes);
  EXPECT_EQ(kept.bushy_grafts, 0u);
  EXPECT_GE(kept.grafted_points, all.grafted_points);
  EXPECT_EQ(validate(bushy, t.cloud.size()), "");
  everything.max_bush_share = share - 0.02;
  Skeleton leafy = t.skeleton;
  const CompleteStats left = complete_skeleton(leafy, t.cloud, 0.03, everything);
  EXPECT_TRUE(left.leafy_bushes);
  EXPECT_EQ(left.bushy_grafts, 1u);
  EXPECT_EQ(left.bushy_points, stats.bushy_points);
  EXPECT_EQ(validate(leafy, t.cloud.size()), "");
}

// The same input gives the same skeleton on one thread and on all of them.
TEST(Complete, IsTheSameOnOneThreadAndOnMany) {
  Trunk t = trunk(0.05);
  add_twig(t.cloud, {0.05, 0, 1.0}, {0.6, 0, 1.3}, 0.01);
  add_twig(t.cloud, {-0.05, 0, 1.4}, {-0.5, 0.2, 1.9}, 0.01);
  share_points(t, 0);
  Skeleton many = t.skeleton, one = t.skeleton;
  complete_skeleton(many, t.cloud, 0.02);
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    complete_skeleton(one, t.cloud, 0.02);
  }
  ASSERT_EQ(many.node_count(), one.node_count());
  EXPECT_GT(many.node_count(), 21u);
  for (NodeId v = 0; v < many.node_count(); ++v) {
    EXPECT_EQ(many[v].position, one[v].position);
    EXPECT_EQ(many[v].points, one[v].points);
  }
}

}  // namespace
}  // namespace treeskel
