/// @file chains.h
/// The skeleton hung from its root and cut into chains: runs of nodes between forks, the unit that
/// radii, meshes and QSM tables work on.
#pragma once

#include "treeskel/skeleton.h"

#include <cstddef>
#include <vector>

namespace treeskel::modeling {

/// A chain: `nodes.front()` is the root or the fork it leaves; the rest are its own nodes, the last
/// one a fork or a tip.
struct Chain {
  std::vector<NodeId> nodes;
  std::ptrdiff_t parent = -1;        ///< chain ending at nodes.front(); -1 for chains leaving the root
  std::vector<std::size_t> children; ///< chains leaving nodes.back()
};

/// The rooted tree and its chains.
struct ChainTree {
  std::vector<NodeId> parent;                  ///< parent node (the root's is itself)
  std::vector<std::vector<NodeId>> children;   ///< child nodes
  std::vector<Chain> chains;                   ///< parents before children
  std::vector<std::ptrdiff_t> chain_of;        ///< chain owning each node (-1 for the root)
};

/// Builds the chains of `skeleton` from its root. A root with one child starts one chain; a root
/// with several starts one chain per child.
/// @throws InputError when the skeleton is empty or not a tree.
ChainTree build_chains(const Skeleton& skeleton);

/// Length of a chain's polyline.
double chain_length(const Skeleton& skeleton, const Chain& chain);

}  // namespace treeskel::modeling
