#include "treeskel/prune.h"

#include <gtest/gtest.h>

#include <cmath>

namespace treeskel {
namespace {

NodeId node(Skeleton& s, double x, double y, double z, std::uint32_t point) {
  SkeletonNode n;
  n.position = {x, y, z};
  n.radius = 0.1;
  n.points = {point};
  return add_node(s, n);
}

TEST(Prune, RemovesShortSpursAndKeepsTheirPoints) {
  // A trunk 0-1-2-3-4 up z, a long branch 2-5-6-7 and a short spur 3-8.
  Skeleton s;
  for (int i = 0; i < 5; ++i) node(s, 0, 0, i, i);
  node(s, 1, 0, 2, 5);
  node(s, 2, 0, 2, 6);
  node(s, 3, 0, 2, 7);
  node(s, 0.3, 0, 3.1, 8);
  for (int i = 0; i < 4; ++i) boost::add_edge(i, i + 1, s.graph);
  boost::add_edge(2, 5, s.graph);
  boost::add_edge(5, 6, s.graph);
  boost::add_edge(6, 7, s.graph);
  boost::add_edge(3, 8, s.graph);
  PruneOptions o;
  o.min_length = 0.5;
  EXPECT_EQ(prune_short_branches(s, 1.0, o), 1u);
  EXPECT_EQ(s.node_count(), 8u);
  EXPECT_EQ(count_branch_points(s.graph), 1u);
  EXPECT_EQ(count_endpoints(s.graph), 3u);  // root, trunk tip, branch tip
  EXPECT_EQ(validate(s, 9), "");
  EXPECT_EQ(s[3].points, (std::vector<std::uint32_t>{3, 8}));
}

// A twig of 0.7 bands straight out of its branch (beyond the radius rule's 1.75 radii plus half a
// band) is kept by default: the shortest branch kept is half a band. A whole band took it.
TEST(Prune, ATwigHalfABandLongOrMoreIsKeptByDefault) {
  Skeleton s;
  for (int i = 0; i < 5; ++i) node(s, 0, 0, i, i);
  node(s, 0.7, 0, 3, 5);
  for (int i = 0; i < 4; ++i) boost::add_edge(i, i + 1, s.graph);
  boost::add_edge(3, 5, s.graph);
  EXPECT_DOUBLE_EQ(prune_length_for(PruneOptions{}, 1.0), 0.5);
  Skeleton kept = s;
  EXPECT_EQ(prune_short_branches(kept, 1.0), 0u);
  EXPECT_EQ(count_branch_points(kept.graph), 1u);
  PruneOptions whole_band;
  whole_band.min_length = 1.0;
  EXPECT_EQ(prune_short_branches(s, 1.0, whole_band), 1u);
  EXPECT_EQ(count_branch_points(s.graph), 0u);
  EXPECT_EQ(validate(s, 6), "");
}

// Two forks a band apart where the tree has one: the second's spur (2.2 bands) goes by default, and
// its points go to the fork; the arms longer than 3 bands stay. Off (a model's), or with the forks
// farther apart than the setting, the spur stays.
TEST(Prune, ASpurAtAForkCloseToAnotherGoes) {
  auto build = [] {
    Skeleton s;
    for (int i = 0; i < 4; ++i) node(s, 0, 0, i, i);  // trunk 0-3; fork A = 3
    for (int i = 1; i <= 4; ++i) node(s, i, 0, 3 + 0.5 * i, 3 + i);  // 4-7: a long arm from A
    node(s, 0, 0, 4, 8);  // fork B, one band above A
    for (int i = 1; i <= 4; ++i) node(s, 0, 0, 4 + i, 8 + i);  // 9-12: a long arm from B
    node(s, -1, 0, 4.5, 13);  // 13-14: the spur from B
    node(s, -2, 0, 5, 14);
    for (int i = 0; i < 3; ++i) boost::add_edge(i, i + 1, s.graph);
    boost::add_edge(3, 4, s.graph);
    for (int i = 4; i < 7; ++i) boost::add_edge(i, i + 1, s.graph);
    boost::add_edge(3, 8, s.graph);
    boost::add_edge(8, 9, s.graph);
    for (int i = 9; i < 12; ++i) boost::add_edge(i, i + 1, s.graph);
    boost::add_edge(8, 13, s.graph);
    boost::add_edge(13, 14, s.graph);
    return s;
  };
  Skeleton s = build();
  ASSERT_EQ(count_branch_points(s.graph), 2u);
  EXPECT_EQ(PruneOptions{}.close_forks, 1.5);
  EXPECT_EQ(prune_spurs_at_close_forks(s, 1.0), 1u);
  EXPECT_EQ(count_branch_points(s.graph), 1u);
  EXPECT_EQ(s.node_count(), 13u);
  EXPECT_EQ(validate(s, 15), "");
  EXPECT_EQ(s[8].points, (std::vector<std::uint32_t>{8, 13, 14}));
  PruneOptions off;
  off.close_forks = 0.0;
  Skeleton kept = build();
  EXPECT_EQ(prune_spurs_at_close_forks(kept, 1.0, off), 0u);
  PruneOptions near;
  near.close_forks = 0.9;  // the forks are a band apart
  EXPECT_EQ(prune_spurs_at_close_forks(kept, 1.0, near), 0u);
  PruneOptions short_spurs;
  short_spurs.close_fork_leaf = 2.0;  // the spur is 2.2 bands long
  EXPECT_EQ(prune_spurs_at_close_forks(kept, 1.0, short_spurs), 0u);
  EXPECT_EQ(count_branch_points(kept.graph), 2u);
}

// A trunk along z whose points lie `spread` from its axis while its nodes' radii say `radius`, and
// a leaf reaching `reach` from the axis at z = 2 (the trunk goes on 2 above it, so the leaf is the
// shorter child of its fork).
Skeleton trunk_with_leaf(double reach, PointCloud& cloud, double radius = 0.6, double spread = 0.2) {
  Skeleton s;
  cloud.positions.clear();
  for (int i = 0; i < 5; ++i) {
    SkeletonNode n;
    n.position = {0, 0, static_cast<double>(i)};
    n.radius = radius;
    for (int k = 0; k < 8; ++k) {
      const double a = k * 3.14159265358979 / 4;
      n.points.push_back(static_cast<std::uint32_t>(cloud.positions.size()));
      cloud.positions.emplace_back(spread * std::cos(a), spread * std::sin(a), i);
    }
    add_node(s, n);
  }
  SkeletonNode leaf;
  leaf.position = {reach, 0, 2};
  leaf.radius = 0.1;
  leaf.points = {static_cast<std::uint32_t>(cloud.positions.size())};
  cloud.positions.push_back(leaf.position);
  add_node(s, leaf);
  for (int i = 0; i < 4; ++i) boost::add_edge(i, i + 1, s.graph);
  boost::add_edge(2, 5, s.graph);
  return s;
}

// Bark points 0.2 from the axis, the nodes' radii 0.6 (as a twig leaving near the fork makes them).
// On the nodes' radii the rule (1.75 radii + half a band = 1.55) removes a leaf reaching 1.4; on the
// points (2.25 times 0.2 + half a band = 0.95) it stays, and one reaching 0.8 goes. Without the cloud,
// or with the factor 0, the nodes' radii decide.
TEST(Prune, TheHostRadiusComesFromItsPoints) {
  PointCloud cloud;
  Skeleton kept = trunk_with_leaf(1.4, cloud);
  EXPECT_DOUBLE_EQ(PruneOptions{}.point_host_factor, 2.25);
  EXPECT_EQ(prune_short_branches(kept, 1.0, PruneOptions{}, &cloud), 0u);
  EXPECT_EQ(count_branch_points(kept.graph), 1u);

  Skeleton on_nodes = trunk_with_leaf(1.4, cloud);
  EXPECT_EQ(prune_short_branches(on_nodes, 1.0), 1u);  // no cloud: the nodes' radii
  Skeleton factor_off = trunk_with_leaf(1.4, cloud);
  PruneOptions off;
  off.point_host_factor = 0.0;
  EXPECT_EQ(prune_short_branches(factor_off, 1.0, off, &cloud), 1u);

  Skeleton spur = trunk_with_leaf(0.8, cloud);
  EXPECT_EQ(prune_short_branches(spur, 1.0, PruneOptions{}, &cloud), 1u);
  EXPECT_EQ(count_branch_points(spur.graph), 0u);
  EXPECT_EQ(validate(spur, cloud.size()), "");
  EXPECT_EQ(spur[2].points.size(), 9u);  // the spur's point went to the fork
}

// The other way round: points 0.6 from the axis (foliage around the host), the nodes' radii 0.2.
// The smaller of the two is the host's radius: the leaf reaching 1.4 stays (2.25 times 0.2 + half a
// band = 0.95), where the points alone (2.25 times 0.6 + 0.5 = 1.85) would remove it.
TEST(Prune, FoliageAroundTheHostDoesNotWidenIt) {
  PointCloud cloud;
  Skeleton s = trunk_with_leaf(1.4, cloud, 0.2, 0.6);
  EXPECT_EQ(prune_short_branches(s, 1.0, PruneOptions{}, &cloud), 0u);
  Skeleton far = trunk_with_leaf(1.4, cloud, 0.2, 0.6);
  PruneOptions wide;
  wide.point_host_factor = 3.0;  // 3 times 0.2 + 0.5 = 1.1: still kept
  EXPECT_EQ(prune_short_branches(far, 1.0, wide, &cloud), 0u);
  Skeleton near = trunk_with_leaf(0.8, cloud, 0.2, 0.6);
  EXPECT_EQ(prune_short_branches(near, 1.0, PruneOptions{}, &cloud), 1u);
}

TEST(Prune, KeepsTheLongestWhenEveryChildIsShort) {
  Skeleton s;
  node(s, 0, 0, 0, 0);
  node(s, 0, 0, 1, 1);
  node(s, 0.2, 0, 1.3, 2);
  node(s, -0.1, 0, 1.1, 3);
  boost::add_edge(0, 1, s.graph);
  boost::add_edge(1, 2, s.graph);
  boost::add_edge(1, 3, s.graph);
  PruneOptions o;
  o.min_length = 1.0;
  EXPECT_EQ(prune_short_branches(s, 1.0, o), 1u);
  EXPECT_EQ(s.node_count(), 3u);
  EXPECT_EQ(s[2].position, Eigen::Vector3d(0.2, 0, 1.3));
  EXPECT_EQ(validate(s, 4), "");
}

}  // namespace
}  // namespace treeskel
