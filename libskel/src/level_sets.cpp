#include "treeskel/level_sets.h"

#include "treeskel/error.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace treeskel {

double mean_distance(const std::vector<Eigen::Vector3d>& positions, const std::vector<std::uint32_t>& points,
                     const Eigen::Vector3d& centre) {
  if (points.empty()) return 0.0;
  double sum = 0.0;
  for (auto i : points) sum += (positions[i] - centre).norm();
  return sum / static_cast<double>(points.size());
}

Skeleton level_set_skeleton(const PointCloud& cloud, const OctreeCells& cells, const CellGraph& graph,
                            const std::vector<bool>& in_tree, const GeodesicField& geodesic,
                            const LevelSetOptions& options) {
  const std::size_t n = cells.cell_count();
  TREESKEL_REQUIRE(in_tree.size() == n && geodesic.distance.size() == n, "cells, flags and distances disagree");
  const double rho = options.band_width > 0.0 ? options.band_width : 2.0 * cells.cell_size;

  std::vector<std::int64_t> band(n, -1);
  for (std::size_t c = 0; c < n; ++c)
    if (in_tree[c] && std::isfinite(geodesic.distance[c]))
      band[c] = static_cast<std::int64_t>(std::floor(geodesic.distance[c] / rho));

  // Components of each band: union over the edges that stay inside one band.
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (std::size_t c = 0; c < n; ++c) {
    if (band[c] < 0) continue;
    for (auto e = graph.offsets[c]; e < graph.offsets[c + 1]; ++e) {
      const auto o = graph.targets[e];
      if (band[o] != band[c]) continue;
      auto a = find(static_cast<std::uint32_t>(c)), b = find(o);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  // Number the components in cell order of their representative (the smallest cell id).
  std::vector<std::int64_t> node_of(n, -1);
  std::vector<std::vector<std::uint32_t>> members;
  for (std::size_t c = 0; c < n; ++c) {
    if (band[c] < 0) continue;
    const auto r = find(static_cast<std::uint32_t>(c));
    if (node_of[r] < 0) {
      node_of[r] = static_cast<std::int64_t>(members.size());
      members.emplace_back();
    }
    node_of[c] = node_of[r];
    members[node_of[c]].push_back(static_cast<std::uint32_t>(c));
  }
  TREESKEL_REQUIRE(!members.empty(), "no cell was reached from the root");

  Skeleton skeleton;
  skeleton.offset = cloud.offset;
  std::vector<SkeletonNode> nodes(members.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, members.size(), 16), [&](const auto& range) {
    for (std::size_t k = range.begin(); k != range.end(); ++k) {
      auto& node = nodes[k];
      for (auto c : members[k]) node.points.insert(node.points.end(), cells.begin(c), cells.end(c));
      std::sort(node.points.begin(), node.points.end());
      node.position = l1_median(cloud.positions, node.points.data(), node.points.data() + node.points.size(),
                                options.median);
      node.radius = mean_distance(cloud.positions, node.points, node.position);
    }
  });
  for (auto& node : nodes) add_node(skeleton, node);

  std::int64_t root = -1;
  for (std::size_t k = 0; k < members.size(); ++k) {
    const auto lowest = *std::min_element(members[k].begin(), members[k].end(), [&](auto a, auto b) {
      return geodesic.distance[a] < geodesic.distance[b] || (geodesic.distance[a] == geodesic.distance[b] && a < b);
    });
    const auto pred = geodesic.predecessor[lowest];
    if (pred < 0) {
      TREESKEL_REQUIRE(root < 0, "the root cells span more than one band component");
      root = static_cast<std::int64_t>(k);
      continue;
    }
    const auto up = node_of[pred];
    TREESKEL_REQUIRE(up >= 0 && up != static_cast<std::int64_t>(k), "a band component has no lower neighbour");
    boost::add_edge(k, static_cast<std::size_t>(up), skeleton.graph);
  }
  TREESKEL_REQUIRE(root >= 0, "no band component holds the root");
  skeleton.root = static_cast<NodeId>(root);

  for (std::size_t c = 0; c < n; ++c)
    if (band[c] < 0) skeleton.noise_points.insert(skeleton.noise_points.end(), cells.begin(c), cells.end(c));
  std::sort(skeleton.noise_points.begin(), skeleton.noise_points.end());
  return skeleton;
}

}  // namespace treeskel
