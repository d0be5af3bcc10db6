// The repair of the sweep (modeling/src/repair.h, private to the library), alone: which branch a
// crossing or a failure thins, when it is left out to be swept apart, and when a fold's forks become
// one join.
#include "../../modeling/src/repair.h"
#include "model_fixtures.h"
#include "treeskel/error.h"

#include <gtest/gtest.h>

#include <vector>

namespace treeskel::modeling::detail {
namespace {

/// A trunk 1 thick at the root up to a fork, then a limb (0.3) and a twig (0.05) leaving it: the
/// nodes each branch starts with, and what the repair needs.
struct Tree {
  Skeleton s = test::straight(1.0, 0.1, 10);
  NodeId fork = 10, limb = 0, twig = 0;
  ChainTree tree;
  std::vector<double> wood;
  TreeScale whole;
  SweepOptions options;
  SweepStats st;
  std::vector<NodeId> detached;
  Tree() {
    test::add_run(s, fork, Eigen::Vector3d(0, 0, 2), 0.08, 10);
    limb = static_cast<NodeId>(s.node_count());
    test::add_run(s, fork, Eigen::Vector3d(0.5, 0, 1.5), 0.03, 5);
    twig = static_cast<NodeId>(s.node_count());
    test::add_run(s, limb + 2, Eigen::Vector3d(0.3, 0.2, 1.4), 0.005, 5);
    tree = build_chains(s);
    wood.assign(s.node_count(), 1e-6);  // every frustum alike: no branch carries much of the wood
    whole.floor_radius = 1e-4;
    whole.limb_radius = 0.09;  // the trunk only
    whole.wood_volume = 1e-6 * static_cast<double>(s.node_count());
    options.max_thinned_share = 0.5;
  }
  /// The identity map of node ids (the attempt's skeleton is the tree's own).
  std::vector<NodeId> same() const {
    std::vector<NodeId> ids(s.node_count());
    for (NodeId v = 0; v < ids.size(); ++v) ids[v] = v;
    return ids;
  }
  /// An attempt of two faces, one of each of two branches (their first nodes, of the given radii).
  static Attempt two_faces(NodeId a, double ra, NodeId b, double rb) {
    Attempt attempt;
    attempt.face_owner = {a, b};
    attempt.owner_radius = {ra, rb};
    return attempt;
  }
};

// Of two crossing faces the thinner branch is thinned by repair_shrink, all it carries with it;
// thinned twice without clearing the crossing, the other one is thinned instead.
TEST(Repair, ACrossingThinsTheThinnerBranchThenTheOther) {
  Tree t;
  Thinning thinning(t.s, t.tree, t.options, t.whole, t.wood, t.st, t.detached);
  const std::vector<NodeId> same = t.same();
  const Attempt crossing = Tree::two_faces(t.limb, 0.1, t.twig, 0.01);
  const double k = t.options.repair_shrink;
  for (int round = 1; round <= 2; ++round) {
    ASSERT_TRUE(thinning.repair({{0, 1}}, false, crossing, same));
    EXPECT_NEAR(thinning.scale()[t.twig + 4], std::pow(k, round), 1e-12) << round;  // its tip too
    EXPECT_EQ(thinning.scale()[t.limb], 1.0);
  }
  ASSERT_TRUE(thinning.repair({{0, 1}}, false, crossing, same));
  EXPECT_NEAR(thinning.scale()[t.limb], k, 1e-12);
  EXPECT_NEAR(thinning.scale()[t.twig], k * k * k, 1e-12);  // the limb carries it
  EXPECT_EQ(thinning.scale()[0], 1.0);
  EXPECT_EQ(t.st.repaired_shrunk, 3u);
  EXPECT_EQ(t.st.repair_rounds, 3);
  EXPECT_TRUE(t.detached.empty());
}

// A twig that could not be swept is thinned up to max_shrinks times, then left out, to be swept
// apart with all it carries.
TEST(Repair, ATwigThatKeepsFailingIsLeftOutToBeSweptApart) {
  Tree t;
  Thinning thinning(t.s, t.tree, t.options, t.whole, t.wood, t.st, t.detached);
  const std::vector<NodeId> same = t.same();
  for (int round = 1; round <= t.options.max_shrinks; ++round) {
    thinning.shrink_failed({t.twig}, same);
    EXPECT_NEAR(thinning.scale()[t.twig], std::pow(t.options.repair_shrink, round), 1e-12) << round;
  }
  EXPECT_TRUE(t.detached.empty());
  thinning.shrink_failed({t.twig}, same);
  EXPECT_EQ(t.st.repaired_dropped, 1u);
  EXPECT_FALSE(thinning.keep()[t.twig]);
  EXPECT_EQ(t.detached.size(), 5u);  // the twig's five nodes
  EXPECT_TRUE(thinning.keep()[t.limb]);
}

// A branch that carries max_thinned_share of the tree's wood or more is left out at once, to be
// swept apart at its own radii, not thinned with all it carries.
TEST(Repair, ABranchCarryingMuchOfTheWoodIsSweptApartNotThinned) {
  Tree t;
  t.options.max_thinned_share = 0.2;  // the limb with its twig carries 10 of 31 frustums
  Thinning thinning(t.s, t.tree, t.options, t.whole, t.wood, t.st, t.detached);
  const std::vector<NodeId> same = t.same();
  ASSERT_TRUE(thinning.repair({{0, 1}}, false, Tree::two_faces(0, 0.1, t.limb, 0.05), same));
  EXPECT_EQ(t.st.repaired_dropped, 1u);
  EXPECT_EQ(t.st.repaired_shrunk, 0u);
  EXPECT_FALSE(thinning.keep()[t.limb]);
  EXPECT_FALSE(thinning.keep()[t.twig]);
  EXPECT_EQ(t.detached.size(), 10u);  // the limb's 5 nodes and the twig's 5
}

// The base carries the whole tree: where a part of it (the root's join, or the base chain) crosses
// another part, the other part is thinned, even when the base's part is the thinner one (a join at
// the root whose thickest arm is a twig of the roots; thinned, the whole tree went with it).
TEST(Repair, WhereTheBaseCrossesAnotherPartTheOtherYields) {
  Tree t;
  Thinning thinning(t.s, t.tree, t.options, t.whole, t.wood, t.st, t.detached);
  const std::vector<NodeId> same = t.same();
  const NodeId base = t.tree.chains.front().nodes[1];
  const double k = t.options.repair_shrink;
  ASSERT_TRUE(thinning.repair({{0, 1}}, false, Tree::two_faces(t.s.root, 0.01, t.limb, 0.05), same));
  EXPECT_NEAR(thinning.scale()[t.limb], k, 1e-12);
  ASSERT_TRUE(thinning.repair({{0, 1}}, false, Tree::two_faces(base, 0.01, t.limb, 0.05), same));
  EXPECT_NEAR(thinning.scale()[t.limb], k * k, 1e-12);
  for (NodeId v : {t.s.root, base, t.fork}) EXPECT_EQ(thinning.scale()[v], 1.0) << v;
}

// The base chain is never left out: thinned to its floor, a failure there is an error.
TEST(Repair, TheBaseIsThinnedToItsFloorButNeverLeftOut) {
  Tree t;
  Thinning thinning(t.s, t.tree, t.options, t.whole, t.wood, t.st, t.detached);
  const std::vector<NodeId> same = t.same();
  const NodeId base = t.tree.chains.front().nodes[1];
  for (int round = 0; round < 2 * t.options.max_shrinks + 2; ++round) {
    try {
      thinning.shrink_failed({base}, same);
    } catch (const Error&) {
      EXPECT_NEAR(thinning.scale()[base], std::pow(t.options.repair_shrink, t.options.max_shrinks), 1e-12);
      EXPECT_TRUE(thinning.keep()[base]);
      EXPECT_TRUE(t.detached.empty());
      return;
    }
  }
  FAIL() << "the base was thinned forever";
}

}  // namespace
}  // namespace treeskel::modeling::detail
