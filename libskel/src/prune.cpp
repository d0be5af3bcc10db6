#include "treeskel/prune.h"

#include "treeskel/geometry.h"

#include <algorithm>

namespace treeskel {

namespace {
/// The most host points whose distances from the host axis give its radius (`point_host_factor`).
constexpr std::size_t kHostSamples = 256;
}  // namespace

double prune_length_for(const PruneOptions& options, double band_width) {
  return options.min_length > 0.0 ? options.min_length : options.min_bands * band_width;
}

std::size_t prune_short_branches(Skeleton& skeleton, double band_width, const PruneOptions& options,
                                 const PointCloud* cloud) {
  const bool host_from_points = cloud != nullptr && options.point_host_factor > 0.0;
  const double min_length = prune_length_for(options, band_width);
  std::size_t removed_total = 0;
  auto& g = skeleton.graph;
  const std::size_t n = boost::num_vertices(g);
  // Removed nodes are cut loose after each round and dropped from the graph once, at the end: the
  // node ids keep their order, so each round sees what it would in a graph compacted every round.
  std::vector<bool> keep(n, true);
  std::size_t alive = n;
  for (;;) {
    if (alive < 3) break;
    const auto parent = parents_from_root(g, skeleton.root);
    std::vector<std::vector<NodeId>> children(n);
    for (NodeId v = 0; v < n; ++v)
      if (v != skeleton.root && keep[v]) children[parent[v]].push_back(v);

    // Every leaf branch: its nodes from the tip down to (not including) the fork, and its length.
    struct Leaf {
      NodeId fork;
      std::vector<NodeId> nodes;
      double length;
    };
    std::vector<std::vector<Leaf>> leaves_at(n);
    for (NodeId v = 0; v < n; ++v) {
      if (v == skeleton.root || !keep[v] || !children[v].empty()) continue;
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

    // The branch a leaf leaves: a few nodes of the fork's parent chain and of its other children.
    auto host_segments = [&](NodeId fork, const Leaf& leaf, std::vector<double>& radii, std::vector<NodeId>& hosts) {
      std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segments;
      radii.assign(1, g[fork].radius);
      hosts.assign(1, fork);
      NodeId u = fork;
      for (int k = 0; k < options.host_nodes && u != skeleton.root; ++k) {
        segments.emplace_back(g[u].position, g[parent[u]].position);
        u = parent[u];
        radii.push_back(g[u].radius);
        hosts.push_back(u);
      }
      for (NodeId c : children[fork]) {
        if (c == leaf.nodes.back()) continue;
        NodeId w = fork;
        for (int k = 0; k < options.host_nodes; ++k) {
          const NodeId next = k == 0 ? c : (children[w].size() == 1 ? children[w].front() : w);
          if (next == w) break;
          segments.emplace_back(g[w].position, g[next].position);
          radii.push_back(g[next].radius);
          hosts.push_back(next);
          w = next;
        }
      }
      if (segments.empty()) segments.emplace_back(g[fork].position, g[fork].position);
      return segments;
    };

    // The distances of the host nodes' points from the host axis, with their median in the middle
    // place; a stride keeps at most kHostSamples of them (dense clouds). False when they have none.
    auto host_spread = [&](const std::vector<NodeId>& host_nodes, const auto& distance_to_host,
                           std::vector<double>& out) {
      std::size_t total = 0;
      for (NodeId h : host_nodes) total += g[h].points.size();
      out.clear();
      if (total == 0) return false;
      const std::size_t stride = (total + kHostSamples - 1) / kHostSamples;
      std::size_t i = 0;
      for (NodeId h : host_nodes)
        for (auto p : g[h].points)
          if (i++ % stride == 0) out.push_back(distance_to_host(cloud->positions[p]));
      std::nth_element(out.begin(), out.begin() + out.size() / 2, out.end());
      return true;
    };

    std::vector<NodeId> cut;
    std::size_t removed = 0;
    std::vector<double> radii, spread;
    std::vector<NodeId> hosts;
    for (NodeId fork = 0; fork < n; ++fork) {
      auto& leaves = leaves_at[fork];
      if (leaves.empty()) continue;
      std::sort(leaves.begin(), leaves.end(), [](const Leaf& a, const Leaf& b) {
        return a.length > b.length || (a.length == b.length && a.nodes.front() < b.nodes.front());
      });
      // A fork whose children are all leaves keeps the longest one: it continues the branch.
      const bool all_leaves = leaves.size() == children[fork].size();
      for (std::size_t i = all_leaves ? 1 : 0; i < leaves.size(); ++i) {
        const Leaf& leaf = leaves[i];
        bool spurious = leaf.length < min_length;
        if (!spurious) {
          // A leaf that never leaves the volume of the branch it grows on is a piece of that branch's
          // surface, not a branch.
          const auto segments = host_segments(fork, leaf, radii, hosts);
          auto distance_to_host = [&](const Eigen::Vector3d& q) {
            double d = 1e300;
            for (const auto& [a, b] : segments) d = std::min(d, point_segment_distance(q, a, b));
            return d;
          };
          // The nodes' median radius; with the cloud, the smaller of it and the points' median spread
          // (a twig leaving at the fork inflates the nodes' radii, foliage around the host its points').
          std::nth_element(radii.begin(), radii.begin() + radii.size() / 2, radii.end());
          double factor = options.radius_factor, host_radius = radii[radii.size() / 2];
          if (host_from_points && host_spread(hosts, distance_to_host, spread)) {
            factor = options.point_host_factor;
            host_radius = std::min(host_radius, spread[spread.size() / 2]);
          }
          double reach = 0.0;
          for (NodeId u : leaf.nodes) reach = std::max(reach, distance_to_host(g[u].position));
          spurious = reach < factor * host_radius + 0.5 * band_width;
        }
        if (!spurious) continue;
        for (auto u : leaf.nodes) {
          auto& pts = g[fork].points;
          pts.insert(pts.end(), g[u].points.begin(), g[u].points.end());
          keep[u] = false;
          cut.push_back(u);
        }
        ++removed;
      }
      std::sort(g[fork].points.begin(), g[fork].points.end());
    }
    if (removed == 0) break;
    for (auto u : cut) boost::clear_vertex(u, g);
    alive -= cut.size();
    removed_total += removed;
  }
  if (removed_total > 0) compact_nodes(skeleton, keep);
  return removed_total;
}

std::size_t prune_spurs_at_close_forks(Skeleton& skeleton, double band_width, const PruneOptions& options) {
  if (!(options.close_forks > 0.0)) return 0;
  auto& g = skeleton.graph;
  const std::size_t n = boost::num_vertices(g);
  std::vector<bool> keep(n, true);
  std::size_t removed = 0;
  // An arm: the nodes from a fork's neighbour along the chain to the next node that is not on a
  // chain (a tip or a fork), and its length from the fork.
  struct Arm {
    double length = 0.0;
    NodeId end;
    std::vector<NodeId> nodes;
  };
  auto walk = [&](NodeId fork, NodeId first) {
    Arm arm{(g[first].position - g[fork].position).norm(), first, {first}};
    NodeId previous = fork;
    while (boost::degree(arm.end, g) == 2) {
      const auto neighbours = boost::adjacent_vertices(arm.end, g);
      const NodeId next = *neighbours.first == previous ? *std::next(neighbours.first) : *neighbours.first;
      arm.length += (g[next].position - g[arm.end].position).norm();
      previous = arm.end;
      arm.end = next;
      arm.nodes.push_back(next);
    }
    return arm;
  };
  for (NodeId fork = 0; fork < n; ++fork) {
    if (!keep[fork] || boost::degree(fork, g) < 3) continue;
    std::vector<Arm> arms;
    for (auto [a, end] = boost::adjacent_vertices(fork, g); a != end; ++a) arms.push_back(walk(fork, *a));
    const bool near = std::any_of(arms.begin(), arms.end(), [&](const Arm& arm) {
      return boost::degree(arm.end, g) >= 3 && arm.length <= options.close_forks * band_width;
    });
    if (!near) continue;
    const Arm* shortest = nullptr;
    for (const Arm& arm : arms)
      if (boost::degree(arm.end, g) == 1 && arm.end != skeleton.root &&
          arm.length <= options.close_fork_leaf * band_width && (!shortest || arm.length < shortest->length))
        shortest = &arm;
    if (!shortest) continue;
    auto& pts = g[fork].points;
    for (NodeId u : shortest->nodes) {
      pts.insert(pts.end(), g[u].points.begin(), g[u].points.end());
      keep[u] = false;
    }
    std::sort(pts.begin(), pts.end());
    for (NodeId u : shortest->nodes) boost::clear_vertex(u, g);
    ++removed;
  }
  if (removed > 0) compact_nodes(skeleton, keep);
  return removed;
}

}  // namespace treeskel
