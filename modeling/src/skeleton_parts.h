// Parts of a skeleton the sweep handles on their own: the branches re-attached where they leave a
// thicker one at a narrow angle, and the pieces (a branch with all it carries, or a path) that are
// swept apart and united with the tree.
#pragma once

#include "treeskel/modeling/chains.h"
#include "treeskel/skeleton.h"

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <vector>

namespace treeskel::modeling::detail {

/// Nodes of the subtree hanging from `top` (with `top`), breadth first; with `skip`, without the
/// nodes it marks below `top` and all they carry.
std::vector<NodeId> subtree(const std::vector<std::vector<NodeId>>& children, NodeId top,
                            const std::vector<char>* skip = nullptr);

/// A branch that leaves a thicker one at less than `min_angle` (radians) runs inside it for a while,
/// and a hull joining the two would be a long fin. Such a branch is re-attached where it comes out of
/// the thicker one's surface: its hidden base is removed and it hangs from the thicker branch's node
/// nearest to where it emerges. `moved` counts them. Returns the new id of every node (-1 for removed
/// ones).
std::vector<std::int64_t> relocate_narrow_branches(Skeleton& sk, double min_angle, std::size_t& moved);

/// The branch of `skeleton` that holds `top`, from the fork it leaves, with all it carries, as a
/// skeleton of its own. The fork is its root and takes the branch's first radius, so that the piece
/// starts inside the parent it hangs from (a branch re-attached where it left a thicker one gets back
/// its hidden base here). Below the fork, a stub follows the parent's path back four fork radii, not
/// past the fork below, at most half as thick as the parent; straight back to the next node (at
/// most one radius) where the branch turns back over its parent by more than 120 degrees, or at a
/// root with several branches (toward the thickest other one).
/// With `depth` (how deep a point lies in the mesh the parent was swept into: negative outside), a
/// piece whose tubes would meet that mesh nowhere (no point of its axis within its radius of it) has
/// its stub follow the parent's path on, node by node, to the first node that lies the stub's
/// radius deep in it (at most 8 nodes, not past the fork below); failing that, its stub goes
/// straight from the fork to the nearest point a stub's radius deep in that mesh, of a grid of
/// points as near the fork as the stub could follow the parent (four fork radii, not past the fork
/// below); failing that too, it stays as it was.
/// With `swept` (by node: whether the mesh the piece is to be united with holds it), the piece
/// leaves out what that mesh holds, with all it carries, and starts at the last node before `top`
/// on its chain that the mesh holds: a branch the sweep re-attached elsewhere stays in the mesh and
/// out of the piece of the branch it left. `members` receives the nodes of `skeleton` the piece
/// holds beyond its fork.
/// With `nearest` too (the point of that mesh's surface nearest to a point), a piece that still meets
/// the mesh nowhere has its stub go straight from the fork through the nearest point of the mesh to
/// the stub's radius inside it: the mesh holds the parent's branch elsewhere than along its skeleton
/// (a chain swept straight from fork to fork, around a skeleton that wanders by several radii), and
/// the piece would be written beside the tree.
using DepthTest = std::function<double(const Eigen::Vector3d&)>;
using NearestTest = std::function<Eigen::Vector3d(const Eigen::Vector3d&)>;
Skeleton piece_of(const Skeleton& skeleton, const ChainTree& tree, NodeId top, const DepthTest& depth = {},
                  const std::vector<char>* swept = nullptr, std::vector<NodeId>* members = nullptr,
                  const NearestTest& nearest = {});

/// The path through `nodes` of `sk` as a skeleton rooted at its first node.
Skeleton path_of(const Skeleton& sk, const std::vector<NodeId>& nodes);

/// The forks on the way from `node` (from the end of its chain, for a chain's first node) up to
/// `ancestor` (each included when it is a fork), when `ancestor` lies that way within `reach` along
/// the skeleton; empty otherwise. Two parts of one line of branches that cross within a few radii
/// of each other are a fold of the line (a trunk that zigzags between forks a centimetre apart),
/// not one branch in the other's way.
std::vector<NodeId> forks_up_to(const Skeleton& skeleton, const ChainTree& tree, NodeId node, NodeId ancestor, double reach);

}  // namespace treeskel::modeling::detail
