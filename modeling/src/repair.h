// The repair of the sweep: how one attempt's failures and crossings thin branches, leave them out
// of the sweep (to be swept apart and united), or make the forks of a fold one join, before the
// skeleton is swept again.
#pragma once

#include "attempt.h"
#include "pieces.h"

#include "treeskel/modeling/chains.h"
#include "treeskel/modeling/sweep.h"
#include "treeskel/skeleton.h"

#include <cstddef>
#include <set>
#include <utility>
#include <vector>

namespace treeskel::modeling::detail {

/// What the repair has done to the skeleton so far, by original node id: which nodes are kept, how
/// much each is thinned, and which forks are made one join. Each attempt sweeps the kept skeleton
/// with its nodes' radii times `scale()`.
class Thinning {
 public:
  /// `wood`: per node, the frustum between it and its parent (see `TreeScale::wood_volume`).
  /// Subtrees left out are appended to `detached`, to be swept apart; `st` counts what is done.
  Thinning(const Skeleton& skeleton, const ChainTree& tree, const SweepOptions& options, const TreeScale& whole,
           std::vector<double> wood, SweepStats& st, std::vector<NodeId>& detached);

  const std::vector<bool>& keep() const { return keep_; }
  const std::vector<double>& scale() const { return scale_; }
  /// Forks made one join after parts between them crossed (original ids, each pair once).
  const std::set<std::pair<NodeId, NodeId>>& fused() const { return fused_; }

  /// Leaves `top` and all it carries out of the sweep (not into `detached`).
  void drop(NodeId top);

  /// Thins the subtrees at the nodes of `failed` (ids of the attempt's skeleton; `old_id` maps them
  /// back) that the mesh could not be built with, or leaves them out.
  /// @throws Error where nothing could change (the trunk turns too sharply for its radius).
  void shrink_failed(const std::vector<NodeId>& failed, const std::vector<NodeId>& old_id);

  /// One round of repair of the crossing faces `pairs` of `attempt` (faces of its triangle soup with
  /// `parts`, else of its assembled mesh): of each two, the thinner part is thinned, or the other one
  /// once thinning the thinner twice has not cleared it; with `parts`, by what the parts' axes say
  /// clears them, else by `repair_shrink`. Two crossing parts of one line of branches (a fold: see
  /// `forks_up_to`) make the forks between them one join instead. False when nothing changed.
  bool repair(const std::vector<std::pair<std::size_t, std::size_t>>& pairs, bool parts, const Attempt& attempt,
              const std::vector<NodeId>& old_id);

 private:
  /// The base chain (the one chain leaving a root with one child) is never swept apart: the rest of
  /// the tree hangs from it.
  bool is_base(NodeId top) const;
  /// The wood `top` carries: its own frustums and all those above it.
  double carried_wood(NodeId top) const;
  bool thin_or_drop(NodeId top, double factor);
  bool fuse_fold(NodeId x, NodeId y, double radius);

  const Skeleton& skeleton_;
  const ChainTree& tree_;
  const SweepOptions& options_;
  const TreeScale& whole_;
  std::vector<double> wood_;
  SweepStats& st_;
  std::vector<NodeId>& detached_;
  std::vector<bool> keep_;
  std::vector<double> scale_;
  std::vector<int> shrinks_;
  std::vector<double> own_scale_;  // per subtree top: the thinning applied to it
  std::set<std::pair<NodeId, NodeId>> fused_;
  std::set<std::pair<NodeId, NodeId>> fused_now_;  // in this round of repair
};

}  // namespace treeskel::modeling::detail
