#include "model_fixtures.h"
#include "treeskel/error.h"
#include "treeskel/modeling/straighten.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace treeskel::modeling {
namespace {

/// A vertical trunk of `radius` from the origin to (0, 0, 4), 200 nodes 2 cm apart, that zigzags
/// sideways by +-`amplitude` with a period of `period` nodes.
Skeleton zigzag_trunk(double radius, double amplitude, int period = 10) {
  Skeleton s;
  SkeletonNode root;
  root.radius = radius;
  s.root = add_node(s, root);
  NodeId prev = s.root;
  for (int i = 1; i <= 200; ++i) {
    SkeletonNode node;
    const double phase = static_cast<double>(i % period) / period;  // a triangle wave
    const double side = i == 200 ? 0.0 : amplitude * (phase < 0.5 ? 4.0 * phase - 1.0 : 3.0 - 4.0 * phase);
    node.position = Eigen::Vector3d(side, 0.0, 0.02 * i);
    node.radius = radius;
    const NodeId v = add_node(s, node);
    boost::add_edge(prev, v, s.graph);
    prev = v;
  }
  return s;
}

/// The largest distance of a node from the vertical axis.
double largest_sway(const Skeleton& s) {
  double out = 0.0;
  for (NodeId v = 0; v < s.node_count(); ++v) out = std::max(out, s[v].position.head<2>().norm());
  return out;
}

TEST(Straighten, AStraightLimbStaysAsItIs) {
  Skeleton s = test::y_shape(0.1, 0.6, 20);
  const Skeleton before = s;
  const StraightenStats st = straighten_limbs(s, 3.0);
  EXPECT_EQ(st.limbs, 2u);  // the trunk going on into one arm, and the other arm
  EXPECT_EQ(st.moved, 0u);
  for (NodeId v = 0; v < s.node_count(); ++v)
    EXPECT_LT((s[v].position - before[v].position).norm(), 1e-12) << v;
}

TEST(Straighten, AThickLimbLosesItsZigzagAndATwigKeepsIt) {
  // The same zigzag of +-5 cm every 20 cm: on a trunk of radius 0.2 it is the skeleton wandering
  // inside the wood, on a twig of radius 0.005 it is the twig's own shape.
  Skeleton trunk = zigzag_trunk(0.2, 0.05), twig = zigzag_trunk(0.005, 0.05);
  const double sway = largest_sway(trunk);
  ASSERT_NEAR(sway, 0.05, 1e-12);
  const StraightenStats st = straighten_limbs(trunk, 3.0);
  EXPECT_LT(largest_sway(trunk), 0.1 * sway);
  EXPECT_GT(st.moved, 100u);
  EXPECT_NEAR(st.largest_shift, 0.05, 0.01);
  straighten_limbs(twig, 3.0);
  EXPECT_GT(largest_sway(twig), 0.85 * sway);
  // Without stiffness nothing moves.
  Skeleton same = zigzag_trunk(0.2, 0.05);
  EXPECT_EQ(straighten_limbs(same, 0.0).moved, 0u);
  EXPECT_NEAR(largest_sway(same), sway, 1e-15);
}

TEST(Straighten, TheRootTheTipsAndTheForksWhereLimbsPartStay) {
  Skeleton s = test::y_shape(0.1, 0.6, 20);
  std::mt19937 rng(7);
  std::normal_distribution<double> jitter(0.0, 0.02);
  for (NodeId v = 0; v < s.node_count(); ++v)
    if (v != s.root && boost::degree(v, s.graph) == 2) s[v].position += Eigen::Vector3d(jitter(rng), jitter(rng), 0.0);
  const Skeleton before = s;
  const NodeId fork = 20;  // the trunk's last node: two arms of equal radius part there
  ASSERT_EQ(boost::degree(fork, s.graph), 3u);
  const StraightenStats st = straighten_limbs(s, 3.0);
  EXPECT_GT(st.moved, 20u);
  for (NodeId v = 0; v < s.node_count(); ++v)
    if (v == s.root || v == fork || boost::degree(v, s.graph) == 1) EXPECT_EQ(s[v].position, before[v].position) << v;
  // Radii, edges and points are the skeleton's.
  for (NodeId v = 0; v < s.node_count(); ++v) EXPECT_EQ(s[v].radius, before[v].radius);
  EXPECT_EQ(boost::num_edges(s.graph), boost::num_edges(before.graph));
  EXPECT_TRUE(is_tree(s.graph));
}

TEST(Straighten, ATwigLeavesTheTrunkWhereTheTrunkMovedTo) {
  // A zigzag trunk with a thin twig at its 100th node, growing out along +y.
  Skeleton s = zigzag_trunk(0.2, 0.05);
  const NodeId fork = 100;
  const Eigen::Vector3d start = s[fork].position;
  ASSERT_GT(std::abs(start.x()), 0.01);  // on a corner of the zigzag
  s[fork].radius = 0.2;
  SkeletonNode first;
  first.position = start;
  first.radius = 0.01;
  NodeId prev = fork;
  std::vector<NodeId> twig;
  for (int i = 1; i <= 20; ++i) {
    first.position = start + Eigen::Vector3d(0.0, 0.02 * i, 0.0);
    const NodeId v = add_node(s, first);
    boost::add_edge(prev, v, s.graph);
    twig.push_back(v);
    prev = v;
  }
  const Skeleton before = s;
  const StraightenStats st = straighten_limbs(s, 3.0);
  const Eigen::Vector3d moved = s[fork].position - before[fork].position;
  EXPECT_GT(moved.norm(), 0.5 * std::abs(start.x()));  // the thin twig did not hold the fork
  // The twig's first node moved several of its radii with the fork; what the report calls the
  // largest shift in radii is what a node's own limb's smoothing moved it: the trunk's, under one.
  EXPECT_GT(moved.norm(), 2.0 * 0.01);
  EXPECT_LT(st.largest_shift_radii, 1.0);
  // The twig went with the fork and kept its direction.
  EXPECT_LT((s[twig.front()].position - before[twig.front()].position - moved).norm(), 0.05 * moved.norm());
  const Eigen::Vector3d was = before[twig.back()].position - before[fork].position;
  const Eigen::Vector3d is = s[twig.back()].position - s[fork].position;
  EXPECT_GT(was.normalized().dot(is.normalized()), std::cos(0.1));
}

TEST(Straighten, ABendMuchLongerThanTheLimbIsThickStays) {
  // A quarter circle of radius 2 m, a limb of radius 0.1: a spread of 0.3 m moves it by about
  // 0.3^2 / (2 * 2) = 2 cm toward the inside, as the header says.
  Skeleton s;
  SkeletonNode node;
  node.radius = 0.1;
  node.position = Eigen::Vector3d(2.0, 0.0, 0.0);
  s.root = add_node(s, node);
  NodeId prev = s.root;
  for (int i = 1; i <= 150; ++i) {
    const double a = 0.5 * M_PI * i / 150;
    node.position = Eigen::Vector3d(2.0 * std::cos(a), 0.0, 2.0 * std::sin(a));
    const NodeId v = add_node(s, node);
    boost::add_edge(prev, v, s.graph);
    prev = v;
  }
  const StraightenStats st = straighten_limbs(s, 3.0);
  EXPECT_LT(st.largest_shift, 0.03);
  EXPECT_GT(st.largest_shift, 0.01);
  const double middle = s[75].position.norm();
  EXPECT_NEAR(middle, 2.0 - 0.3 * 0.3 / 4.0, 0.005);
}

TEST(Straighten, RefusesANegativeFactor) {
  Skeleton s = test::straight(1.0, 0.1);
  EXPECT_THROW(straighten_limbs(s, -1.0), OptionError);
  EXPECT_THROW(straighten_limbs(s, std::nan("")), OptionError);
  EXPECT_THROW(straighten_limbs(s, INFINITY), OptionError);
  Skeleton empty;
  EXPECT_THROW(straighten_limbs(empty, 3.0), InputError);
}

}  // namespace
}  // namespace treeskel::modeling
