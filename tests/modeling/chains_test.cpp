#include "model_fixtures.h"
#include "treeskel/error.h"
#include "treeskel/modeling/chains.h"

#include <gtest/gtest.h>

namespace treeskel::modeling {
namespace {

TEST(Chains, StraightSkeletonIsOneChainFromTheRoot) {
  const Skeleton s = test::straight(2.0, 0.1, 10);
  const ChainTree t = build_chains(s);
  ASSERT_EQ(t.chains.size(), 1u);
  EXPECT_EQ(t.chains[0].nodes.size(), 11u);
  EXPECT_EQ(t.chains[0].nodes.front(), s.root);
  EXPECT_EQ(t.chains[0].parent, -1);
  EXPECT_NEAR(chain_length(s, t.chains[0]), 2.0, 1e-12);
}

TEST(Chains, YHasATrunkChainAndTwoArmsHangingFromIt) {
  const Skeleton s = test::y_shape(0.1, 0.6, 5);
  const ChainTree t = build_chains(s);
  ASSERT_EQ(t.chains.size(), 3u);
  EXPECT_EQ(t.chains[0].children, (std::vector<std::size_t>{1, 2}));
  for (std::size_t c : {1u, 2u}) {
    EXPECT_EQ(t.chains[c].parent, 0);
    EXPECT_EQ(t.chains[c].nodes.front(), t.chains[0].nodes.back());
    EXPECT_TRUE(t.children[t.chains[c].nodes.back()].empty());
  }
  // Every node but the root belongs to exactly one chain.
  std::vector<int> owners(s.node_count(), 0);
  for (const auto& c : t.chains)
    for (std::size_t i = 1; i < c.nodes.size(); ++i) ++owners[c.nodes[i]];
  for (NodeId v = 0; v < s.node_count(); ++v) EXPECT_EQ(owners[v], v == s.root ? 0 : 1) << v;
}

TEST(Chains, RootWithTwoChildrenStartsTwoChains) {
  Skeleton s;
  SkeletonNode n;
  s.root = add_node(s, n);
  test::add_run(s, s.root, Eigen::Vector3d(1, 0, 1), 0.1, 3);
  test::add_run(s, s.root, Eigen::Vector3d(-1, 0, 1), 0.1, 3);
  const ChainTree t = build_chains(s);
  ASSERT_EQ(t.chains.size(), 2u);
  EXPECT_EQ(t.chains[0].parent, -1);
  EXPECT_EQ(t.chains[1].parent, -1);
}

TEST(Chains, RefusesEmptyAndCyclicSkeletons) {
  EXPECT_THROW(build_chains(Skeleton{}), InputError);
  Skeleton s = test::straight(1.0, 0.1, 3);
  boost::add_edge(0, 3, s.graph);
  EXPECT_THROW(build_chains(s), InputError);
}

}  // namespace
}  // namespace treeskel::modeling
