#include "treeskel/eval/tree_generator.h"

#include <gtest/gtest.h>

#include <map>

namespace treeskel::eval {
namespace {

TEST(TreeGenerator, GrowsAConnectedTaperingTreeThatObeysThePipeModel) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    GrowOptions o;
    o.seed = seed;
    const GrownTree tree = grow_tree(o);
    ASSERT_GT(tree.cylinders.size(), 50u);
    ASSERT_EQ(tree.parent.size(), tree.cylinders.size());
    EXPECT_EQ(tree.parent[0], -1);
    std::map<int, std::vector<int>> children;
    for (std::size_t i = 1; i < tree.cylinders.size(); ++i) {
      const int p = tree.parent[i];
      ASSERT_GE(p, 0);
      ASSERT_LT(p, static_cast<int>(i));
      EXPECT_LT((tree.cylinders[i].a - tree.cylinders[p].b).norm(), 1e-12);  // connected
      children[p].push_back(static_cast<int>(i));
    }
    for (std::size_t i = 0; i < tree.cylinders.size(); ++i) {
      const auto& c = tree.cylinders[i];
      EXPECT_GT(c.radius_b, 0.0);
      EXPECT_LE(c.radius_b, c.radius_a + 1e-12);  // never thicker toward the tip
    }
    for (const auto& [p, kids] : children) {
      double area = 0.0;
      for (int k : kids) area += tree.cylinders[k].radius_a * tree.cylinders[k].radius_a;
      const double end = tree.cylinders[p].radius_b;
      EXPECT_NEAR(area, end * end, 1e-9 * end * end) << "seed " << seed << " cylinder " << p;
    }
  }
}

}  // namespace
}  // namespace treeskel::eval
