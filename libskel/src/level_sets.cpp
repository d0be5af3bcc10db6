#include "treeskel/level_sets.h"

#include "treeskel/error.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>

namespace treeskel {

double mean_distance(const std::vector<Eigen::Vector3d>& positions, const std::vector<std::uint32_t>& points,
                     const Eigen::Vector3d& centre) {
  if (points.empty()) return 0.0;
  double sum = 0.0;
  for (auto i : points) sum += (positions[i] - centre).norm();
  return sum / static_cast<double>(points.size());
}

double band_width_for(const LevelSetOptions& options, const OctreeCells& cells) {
  return options.band_width > 0.0 ? options.band_width : 2.0 * cells.cell_size;
}

Skeleton level_set_skeleton(const PointCloud& cloud, const OctreeCells& cells, const CellGraph& graph,
                            const std::vector<bool>& in_tree, const GeodesicField& geodesic,
                            const LevelSetOptions& options) {
  const std::size_t n = cells.cell_count();
  TREESKEL_REQUIRE(in_tree.size() == n && geodesic.distance.size() == n, "cells, flags and distances disagree");
  const double rho = band_width_for(options, cells);

  std::vector<std::int64_t> band(n, -1);
  for (std::size_t c = 0; c < n; ++c)
    if (in_tree[c] && std::isfinite(geodesic.distance[c]))
      band[c] = static_cast<std::int64_t>(std::floor(geodesic.distance[c] / rho));

  // Components of each band: union over the edges that stay inside one band, in parallel. A root is
  // only ever linked under a smaller one, so each component's root is its smallest cell, whatever the
  // order of the unions.
  std::vector<std::atomic<std::uint32_t>> link(n);
  for (std::size_t c = 0; c < n; ++c) link[c].store(static_cast<std::uint32_t>(c), std::memory_order_relaxed);
  const auto find = [&](std::uint32_t v) {
    for (;;) {
      std::uint32_t up = link[v].load(std::memory_order_acquire);
      if (up == v) return v;
      const std::uint32_t next = link[up].load(std::memory_order_acquire);
      if (next != up) link[v].compare_exchange_weak(up, next, std::memory_order_acq_rel);  // halve the path
      v = next;
    }
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
    for (std::size_t c = range.begin(); c != range.end(); ++c) {
      if (band[c] < 0) continue;
      for (auto e = graph.offsets[c]; e < graph.offsets[c + 1]; ++e) {
        const auto o = graph.targets[e];
        if (o < c || band[o] != band[c]) continue;  // each edge once
        for (std::uint32_t a = find(static_cast<std::uint32_t>(c)), b = find(o); a != b; a = find(a), b = find(b)) {
          if (a < b) std::swap(a, b);
          std::uint32_t expected = a;  // the larger root goes under the smaller, if still a root
          if (link[a].compare_exchange_strong(expected, b, std::memory_order_acq_rel)) break;
        }
      }
    }
  });
  // Number the components in cell order of their representative (the smallest cell id).
  std::vector<std::int64_t> comp_of(n, -1);
  std::vector<std::vector<std::uint32_t>> members;
  for (std::size_t c = 0; c < n; ++c) {
    if (band[c] < 0) continue;
    const auto r = find(static_cast<std::uint32_t>(c));
    if (comp_of[r] < 0) {
      comp_of[r] = static_cast<std::int64_t>(members.size());
      members.emplace_back();
    }
    comp_of[c] = comp_of[r];
    members[comp_of[c]].push_back(static_cast<std::uint32_t>(c));
  }
  TREESKEL_REQUIRE(!members.empty(), "no cell was reached from the root");
  const std::size_t m = members.size();

  // Each component hangs from the lower component it shares the most graph edges with (the band just
  // below first): the branch it grows out of. Only the root component, which holds the root cells,
  // has none. Every other one has at least its lowest cell's shortest-path predecessor below it.
  std::vector<std::int64_t> below(m, -1);
  std::vector<std::int64_t> comp_band(m);
  std::vector<std::uint8_t> has_pred(m, 1);  // bytes, not bits: written from several threads
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, m, 64), [&](const auto& range) {
    std::vector<std::pair<std::int64_t, std::uint32_t>> links;  // (lower component, edges)
    for (std::size_t k = range.begin(); k != range.end(); ++k) {
      const auto lowest = *std::min_element(members[k].begin(), members[k].end(), [&](auto a, auto b) {
        return geodesic.distance[a] < geodesic.distance[b] || (geodesic.distance[a] == geodesic.distance[b] && a < b);
      });
      comp_band[k] = band[lowest];
      const auto pred = geodesic.predecessor[lowest];
      if (pred < 0) {
        has_pred[k] = 0;
        continue;
      }
      links.clear();
      for (auto c : members[k])
        for (auto e = graph.offsets[c]; e < graph.offsets[c + 1]; ++e) {
          const auto o = graph.targets[e];
          if (band[o] < 0 || band[o] >= comp_band[k]) continue;
          links.emplace_back(comp_of[o], 1);
        }
      std::sort(links.begin(), links.end());
      std::int64_t best = comp_of[pred];
      std::int64_t best_band = -1;
      std::size_t best_count = 0;
      for (std::size_t i = 0; i < links.size();) {
        std::size_t j = i;
        while (j < links.size() && links[j].first == links[i].first) ++j;
        const auto candidate = links[i].first;
        const auto candidate_band = band[members[candidate].front()];
        if (candidate_band > best_band || (candidate_band == best_band && j - i > best_count)) {
          best = candidate;
          best_band = candidate_band;
          best_count = j - i;
        }
        i = j;
      }
      below[k] = best;
    }
  });
  std::int64_t root = -1;
  for (std::size_t k = 0; k < m; ++k) {
    if (!has_pred[k]) {
      TREESKEL_REQUIRE(root < 0, "the root cells span more than one band component");
      root = static_cast<std::int64_t>(k);
      continue;
    }
    TREESKEL_REQUIRE(below[k] >= 0 && below[k] != static_cast<std::int64_t>(k), "a band component has no lower neighbour");
  }
  TREESKEL_REQUIRE(root >= 0, "no band component holds the root");

  // Band by band, from the root up: siblings of one band (components hanging from the same node) that
  // lie closer to each other than a share of that node's radius are pieces of one ring broken by sparse
  // sampling, and become one node. A real fork's branches part by more than that a band or two higher.
  std::vector<std::uint32_t> merged_into(m);
  std::iota(merged_into.begin(), merged_into.end(), 0u);
  auto owner = [&](std::uint32_t k) {
    while (merged_into[k] != k) k = merged_into[k] = merged_into[merged_into[k]];
    return k;
  };
  std::vector<SkeletonNode> nodes(m);
  auto make_node = [&](std::uint32_t k) {
    auto& node = nodes[k];
    node.points.clear();
    for (auto c : members[k]) node.points.insert(node.points.end(), cells.begin(c), cells.end(c));
    std::sort(node.points.begin(), node.points.end());
    node.position = l1_median(cloud.positions, node.points.data(), node.points.data() + node.points.size(), options.median);
    node.radius = mean_distance(cloud.positions, node.points, node.position);
  };
  // Every component's node at once, in parallel (a band of the trunk holds one or two components, too
  // few to share among threads): the sweep below remakes only the nodes that absorb a sibling.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, m, 8), [&](const auto& range) {
    for (std::size_t k = range.begin(); k != range.end(); ++k) make_node(static_cast<std::uint32_t>(k));
  });
  std::vector<bool> grown(m, false);  // absorbed a sibling: its node is remade
  std::vector<std::uint32_t> order(m);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return comp_band[a] < comp_band[b]; });
  for (std::size_t first = 0; first < m;) {
    std::size_t last = first;
    while (last < m && comp_band[order[last]] == comp_band[order[first]]) ++last;
    // Siblings of this band, grouped by the (final) node they hang from.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> by_parent;  // (parent, component)
    for (std::size_t i = first; i < last; ++i) {
      const auto k = order[i];
      if (below[k] >= 0) {
        below[k] = owner(static_cast<std::uint32_t>(below[k]));
        by_parent.emplace_back(static_cast<std::uint32_t>(below[k]), k);
      }
    }
    std::sort(by_parent.begin(), by_parent.end());
    if (options.join_factor > 0.0)
      for (std::size_t i = 0; i < by_parent.size();) {
        std::size_t j = i;
        while (j < by_parent.size() && by_parent[j].first == by_parent[i].first) ++j;
        const double limit = options.join_factor * nodes[by_parent[i].first].radius;
        for (std::size_t a = i; a < j; ++a)
          for (std::size_t b = a + 1; b < j; ++b) {
            const auto ka = owner(by_parent[a].second), kb = owner(by_parent[b].second);
            if (ka == kb) continue;
            double gap = std::numeric_limits<double>::infinity();
            for (auto ca : members[ka])
              for (auto cb : members[kb]) gap = std::min(gap, (cells.medians[ca] - cells.medians[cb]).norm());
            if (gap >= limit) continue;
            const auto keep = std::min(ka, kb), gone = std::max(ka, kb);
            members[keep].insert(members[keep].end(), members[gone].begin(), members[gone].end());
            members[gone].clear();
            merged_into[gone] = keep;
            grown[keep] = true;
          }
        i = j;
      }
    std::vector<std::uint32_t> band_nodes;
    for (std::size_t i = first; i < last; ++i)
      if (owner(order[i]) == order[i] && grown[order[i]]) band_nodes.push_back(order[i]);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, band_nodes.size(), 4), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) make_node(band_nodes[i]);
    });
    first = last;
  }

  Skeleton skeleton;
  skeleton.offset = cloud.offset;
  std::vector<std::int64_t> node_id(m, -1);
  std::size_t kept = 0;
  for (std::size_t k = 0; k < m; ++k)
    if (owner(static_cast<std::uint32_t>(k)) == k) node_id[k] = static_cast<std::int64_t>(kept++);
  SkeletonGraph sized(kept);
  swap_graphs(skeleton.graph, sized);
  for (std::size_t k = 0; k < m; ++k)
    if (node_id[k] >= 0) skeleton[static_cast<NodeId>(node_id[k])] = std::move(nodes[k]);
  for (std::size_t k = 0; k < m; ++k)
    if (node_id[k] >= 0 && below[k] >= 0)
      boost::add_edge(static_cast<std::size_t>(node_id[k]), static_cast<std::size_t>(node_id[owner(static_cast<std::uint32_t>(below[k]))]),
                      skeleton.graph);
  skeleton.root = static_cast<NodeId>(node_id[root]);

  for (std::size_t c = 0; c < n; ++c)
    if (band[c] < 0) skeleton.noise_points.insert(skeleton.noise_points.end(), cells.begin(c), cells.end(c));
  skeleton.noise_points.insert(skeleton.noise_points.end(), cells.outliers.begin(), cells.outliers.end());
  std::sort(skeleton.noise_points.begin(), skeleton.noise_points.end());
  return skeleton;
}

}  // namespace treeskel
