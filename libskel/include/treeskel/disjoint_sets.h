/// @file disjoint_sets.h
/// Union-find over the integers 0..n-1 (path halving; the smaller index stays the representative,
/// so results do not depend on the order of the unions' arguments).
#pragma once

#include <cstddef>
#include <numeric>
#include <utility>
#include <vector>

namespace treeskel {

template <class Index>
class DisjointSets {
public:
  explicit DisjointSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), Index{0}); }
  /// Representative of the set holding `v`.
  Index find(Index v) {
    while (parent_[v] != v) v = parent_[v] = parent_[parent_[v]];
    return v;
  }
  /// Joins the sets of `a` and `b`; false if they were one set already.
  bool unite(Index a, Index b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    if (b < a) std::swap(a, b);
    parent_[b] = a;
    return true;
  }

private:
  std::vector<Index> parent_;
};

}  // namespace treeskel
