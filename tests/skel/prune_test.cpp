#include "treeskel/prune.h"

#include <gtest/gtest.h>

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
