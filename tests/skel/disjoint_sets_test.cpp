#include "treeskel/disjoint_sets.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>

namespace treeskel {
namespace {

TEST(DisjointSets, StartsAsSingletons) {
  DisjointSets<std::uint32_t> sets(5);
  for (std::uint32_t v = 0; v < 5; ++v) EXPECT_EQ(sets.find(v), v);
}

TEST(DisjointSets, UniteJoinsOnceAndTheSmallestIndexRepresents) {
  DisjointSets<std::uint32_t> sets(6);
  EXPECT_TRUE(sets.unite(4, 2));
  EXPECT_TRUE(sets.unite(5, 4));
  EXPECT_FALSE(sets.unite(2, 5));  // already one set
  EXPECT_EQ(sets.find(5), 2u);
  EXPECT_EQ(sets.find(4), 2u);
  EXPECT_EQ(sets.find(3), 3u);
  EXPECT_TRUE(sets.unite(3, 0));
  EXPECT_TRUE(sets.unite(5, 3));
  for (std::uint32_t v : {2u, 3u, 4u, 5u}) EXPECT_EQ(sets.find(v), 0u);
  EXPECT_EQ(sets.find(1), 1u);
}

// The sets and their representatives do not depend on the order of the unions or of their arguments.
TEST(DisjointSets, ResultDoesNotDependOnOrder) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<std::uint32_t> pick(0, 199);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs(150);
  for (auto& p : pairs) p = {pick(rng), pick(rng)};
  auto representatives = [](const std::vector<std::pair<std::uint32_t, std::uint32_t>>& order, bool swap) {
    DisjointSets<std::uint32_t> sets(200);
    std::size_t joins = 0;
    for (auto [a, b] : order) joins += swap ? sets.unite(b, a) : sets.unite(a, b);
    std::vector<std::uint32_t> out(200);
    for (std::uint32_t v = 0; v < 200; ++v) out[v] = sets.find(v);
    out.push_back(static_cast<std::uint32_t>(joins));
    return out;
  };
  const auto first = representatives(pairs, false);
  for (int round = 0; round < 5; ++round) {
    std::shuffle(pairs.begin(), pairs.end(), rng);
    EXPECT_EQ(representatives(pairs, round % 2 == 1), first);
  }
  // Each representative is the smallest member of its set.
  for (std::uint32_t v = 0; v < 200; ++v) EXPECT_LE(first[v], v);
}

}  // namespace
}  // namespace treeskel
