#include "repair.h"

#include "skeleton_parts.h"
#include "treeskel/error.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace treeskel::modeling::detail {

Thinning::Thinning(const Skeleton& skeleton, const ChainTree& tree, const SweepOptions& options, const TreeScale& whole,
                   std::vector<double> wood, SweepStats& st, std::vector<NodeId>& detached)
    : skeleton_(skeleton),
      tree_(tree),
      options_(options),
      whole_(whole),
      wood_(std::move(wood)),
      st_(st),
      detached_(detached),
      keep_(skeleton.node_count(), true),
      scale_(skeleton.node_count(), 1.0),
      shrinks_(skeleton.node_count(), 0),
      own_scale_(skeleton.node_count(), 1.0) {}

void Thinning::drop(NodeId top) {
  for (NodeId v : subtree(tree_.children, top)) keep_[v] = false;
}

bool Thinning::is_base(NodeId top) const {
  return top == skeleton_.root || (tree_.parent[top] == skeleton_.root && tree_.children[skeleton_.root].size() == 1);
}

double Thinning::carried_wood(NodeId top) const {
  double sum = 0.0;
  for (NodeId v : subtree(tree_.children, top)) sum += wood_[v];
  return sum;
}

// Thins a subtree by `factor`, down to repair_shrink^max_shrinks of its radius (twice that power for
// a limb), then leaves it out (a limb is down to 0.7^6 = 12% of its radius by then); false when
// nothing changed (the trunk, which may not go, at its floor). A branch that carries
// `max_thinned_share` of the tree's wood or more is left out at once, to be swept apart at its own
// radii and united with the tree: thinning it thinned all it carries (a synthetic tree's limb that
// bore 89% of its crown was halved in radius, and its mesh held 0.39 of the true volume; swept apart
// and united, 0.80).
bool Thinning::thin_or_drop(NodeId top, double factor) {
  const auto& g = skeleton_.graph;
  const bool limb = g[top].radius >= whole_.limb_radius;
  if (!is_base(top) && whole_.wood_volume > 0.0 && carried_wood(top) >= options_.max_thinned_share * whole_.wood_volume) {
    drop(top);
    for (NodeId v : subtree(tree_.children, top)) detached_.push_back(v);
    ++st_.repaired_dropped;
    return true;
  }
  const int budget = (limb && !is_base(top) ? 2 : 1) * options_.max_shrinks;
  const double floor = std::pow(options_.repair_shrink, budget);
  const bool at_floor = own_scale_[top] <= floor * (1.0 + 1e-9);
  // A branch that would start thinner than the floor radius is swept apart too.
  const bool too_thin = g[top].radius * own_scale_[top] * factor < whole_.floor_radius * (1.0 - 1e-9);
  if (own_scale_[top] * factor < floor * (1.0 - 1e-9) || too_thin) {
    // A twig is swept apart at once; a limb is first thinned to its floor.
    if (!is_base(top) && (!limb || at_floor || too_thin)) {
      drop(top);
      for (NodeId v : subtree(tree_.children, top)) detached_.push_back(v);
      ++st_.repaired_dropped;
      return true;
    }
    if (at_floor) return false;
    factor = floor / own_scale_[top];
  }
  for (NodeId v : subtree(tree_.children, top)) scale_[v] *= factor;
  own_scale_[top] *= factor;
  ++shrinks_[top];
  ++st_.repaired_shrunk;
  return true;
}

void Thinning::shrink_failed(const std::vector<NodeId>& failed, const std::vector<NodeId>& old_id) {
  std::set<NodeId> tops;
  for (NodeId v : failed) tops.insert(old_id[v]);
  bool any = false;
  for (NodeId top : tops) any |= thin_or_drop(top, options_.repair_shrink);
  if (!any) throw Error("could not sweep the trunk: it turns too sharply for its radius");
}

// Two crossing parts of one line of branches within a few radii of each other (a fold: see
// forks_up_to) make the forks between them one join, once: thinning the part above would thin all it
// carries, which near the base is the whole tree (a synthetic tree's trunk zigzagging over its first
// 5 cm was thinned to an eighth of its radius, its mesh 2% of its wood).
bool Thinning::fuse_fold(NodeId x, NodeId y, double radius) {
  for (const auto& [low, high] : {std::pair{x, y}, std::pair{y, x}}) {
    const auto forks = forks_up_to(skeleton_, tree_, low, high, options_.join_reach * radius);
    bool fresh = false;
    for (std::size_t i = 1; i < forks.size(); ++i) {
      const auto pair = std::minmax(forks[i - 1], forks[i]);
      if (fused_.insert(pair).second) fused_now_.insert(pair);
      fresh |= fused_now_.count(pair) > 0;
    }
    if (fresh) return true;
  }
  return false;
}

bool Thinning::repair(const std::vector<std::pair<std::size_t, std::size_t>>& pairs, bool parts, const Attempt& a,
                      const std::vector<NodeId>& old_id) {
  ++st_.repair_rounds;
  fused_now_.clear();
  std::map<NodeId, double> factor;
  bool any = false;
  for (const auto& [f1, f2] : pairs) {
    const bool first_thinner = a.owner_radius[f1] <= a.owner_radius[f2];
    const NodeId thin = old_id[a.face_owner[first_thinner ? f1 : f2]];
    const NodeId thick = old_id[a.face_owner[first_thinner ? f2 : f1]];
    if (fuse_fold(thin, thick, std::max(a.owner_radius[f1], a.owner_radius[f2]))) {
      any = true;
      continue;
    }
    // The base carries the whole tree: where it crosses another part, the other yields (a join at
    // the root of TreeLS's pine, among the twigs of its roots, crossed the stem above it, and the
    // base thinned to half its radius took the whole tree's mesh to 23% of its wood).
    const bool swap = !is_base(thick) &&
                      (is_base(thin) || (shrinks_[thin] >= 2 && shrinks_[thick] < shrinks_[thin]));
    double f = options_.repair_shrink;
    if (parts)
      if (const auto clear = clearing_factor(a, a.face_part[first_thinner != swap ? f1 : f2], a.face_part[first_thinner != swap ? f2 : f1]))
        f = std::max(*clear, options_.repair_shrink * options_.repair_shrink);
    const auto [it, fresh] = factor.emplace(swap ? thick : thin, f);
    if (!fresh) it->second = std::min(it->second, f);
  }
  for (const auto& [top, f] : factor)
    if (keep_[top]) any |= thin_or_drop(top, f);
  return any;
}

}  // namespace treeskel::modeling::detail
