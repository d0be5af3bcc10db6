#include "treeskel/prune.h"

#include <algorithm>

namespace treeskel {

std::size_t prune_short_branches(Skeleton& skeleton, double band_width, const PruneOptions& options) {
  const double min_length = options.min_length > 0.0 ? options.min_length : 2.0 * band_width;
  std::size_t removed_total = 0;
  for (;;) {
    auto& g = skeleton.graph;
    const std::size_t n = boost::num_vertices(g);
    if (n < 3) break;
    const auto parent = parents_from_root(g, skeleton.root);
    std::vector<std::vector<NodeId>> children(n);
    for (NodeId v = 0; v < n; ++v)
      if (v != skeleton.root) children[parent[v]].push_back(v);

    // Every leaf branch: its nodes from the tip down to (not including) the fork, and its length.
    struct Leaf {
      NodeId fork;
      std::vector<NodeId> nodes;
      double length;
    };
    std::vector<std::vector<Leaf>> leaves_at(n);
    for (NodeId v = 0; v < n; ++v) {
      if (v == skeleton.root || !children[v].empty()) continue;
      Leaf leaf{v, {}, 0.0};
      NodeId u = v;
      for (;;) {
        leaf.nodes.push_back(u);
        const NodeId p = parent[u];
        leaf.length += (g[u].position - g[p].position).norm();
        if (p == skeleton.root || children[p].size() != 1) {
          leaf.fork = p;
          break;
        }
        u = p;
      }
      if (children[leaf.fork].size() >= 2) leaves_at[leaf.fork].push_back(std::move(leaf));
    }

    std::vector<bool> keep(n, true);
    std::size_t removed = 0;
    for (NodeId fork = 0; fork < n; ++fork) {
      auto& leaves = leaves_at[fork];
      if (leaves.empty()) continue;
      const double limit = std::max(min_length, options.radius_factor * g[fork].radius);
      std::sort(leaves.begin(), leaves.end(), [](const Leaf& a, const Leaf& b) {
        return a.length > b.length || (a.length == b.length && a.nodes.front() < b.nodes.front());
      });
      // A fork whose children are all leaves keeps the longest one: it continues the branch.
      const bool all_leaves = leaves.size() == children[fork].size();
      for (std::size_t i = all_leaves ? 1 : 0; i < leaves.size(); ++i) {
        if (leaves[i].length >= limit) continue;
        for (auto u : leaves[i].nodes) {
          auto& pts = g[fork].points;
          pts.insert(pts.end(), g[u].points.begin(), g[u].points.end());
          keep[u] = false;
        }
        ++removed;
      }
      std::sort(g[fork].points.begin(), g[fork].points.end());
    }
    if (removed == 0) break;
    compact_nodes(skeleton, keep);
    removed_total += removed;
  }
  return removed_total;
}

}  // namespace treeskel
