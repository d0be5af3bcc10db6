#include "treeskel/geodesic.h"

#include "treeskel/error.h"

#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/graph/dijkstra_shortest_paths.hpp>

#include <algorithm>
#include <limits>

namespace treeskel {

double root_slice_for(const RootOptions& options, const OctreeCells& cells) {
  return options.slice > 0.0 ? options.slice : 2.0 * cells.cell_size;
}

std::vector<std::uint32_t> select_root_cells(const OctreeCells& cells, const CellGraph& graph,
                                             const std::vector<bool>& in_tree, const RootOptions& options) {
  const std::size_t n = cells.cell_count();
  TREESKEL_REQUIRE(in_tree.size() == n, "one flag per cell is needed");
  TREESKEL_REQUIRE(options.up.norm() > 0.0, "the up axis must not be zero");
  const Eigen::Vector3d up = options.up.normalized();
  std::int64_t best = -1;
  double best_value = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < n; ++c) {
    if (!in_tree[c]) continue;
    const double value = options.point ? (cells.medians[c] - *options.point).squaredNorm() : cells.medians[c].dot(up);
    if (value < best_value) {
      best_value = value;
      best = static_cast<std::int64_t>(c);
    }
  }
  TREESKEL_REQUIRE(best >= 0, "no cell is in the tree");
  if (options.point) return {static_cast<std::uint32_t>(best)};

  const double slice = root_slice_for(options, cells);
  const double top = cells.medians[best].dot(up) + slice;
  std::vector<bool> taken(n, false);
  std::vector<std::uint32_t> roots{static_cast<std::uint32_t>(best)};
  taken[best] = true;
  for (std::size_t i = 0; i < roots.size(); ++i) {
    const auto c = roots[i];
    for (auto e = graph.offsets[c]; e < graph.offsets[c + 1]; ++e) {
      const auto o = graph.targets[e];
      if (!taken[o] && in_tree[o] && cells.medians[o].dot(up) <= top) {
        taken[o] = true;
        roots.push_back(o);
      }
    }
  }
  std::sort(roots.begin(), roots.end());
  return roots;
}

GeodesicField geodesic_distance(const CellGraph& graph, const std::vector<std::uint32_t>& sources) {
  using Csr = boost::compressed_sparse_row_graph<boost::directedS, boost::no_property, double>;
  const std::size_t n = graph.vertex_count();
  // A virtual source joined to every root cell by a zero-length edge turns the multi-source problem
  // into a single-source one. Edges must be listed by source: cells first, then the virtual source.
  std::vector<std::pair<std::size_t, std::size_t>> edges;
  std::vector<double> weights;
  edges.reserve(graph.targets.size() + sources.size());
  weights.reserve(edges.capacity());
  for (std::size_t c = 0; c < n; ++c)
    for (auto e = graph.offsets[c]; e < graph.offsets[c + 1]; ++e) {
      edges.emplace_back(c, graph.targets[e]);
      weights.push_back(graph.weights[e]);
    }
  for (auto s : sources) {
    TREESKEL_REQUIRE(s < n, "a root cell is out of range");
    edges.emplace_back(n, s);
    weights.push_back(0.0);
  }
  const Csr csr(boost::edges_are_sorted, edges.begin(), edges.end(), weights.begin(), n + 1);
  std::vector<double> distance(n + 1);
  std::vector<std::size_t> predecessor(n + 1);
  boost::dijkstra_shortest_paths(
      csr, n,
      boost::weight_map(boost::get(boost::edge_bundle, csr))
          .distance_map(boost::make_iterator_property_map(distance.begin(), boost::get(boost::vertex_index, csr)))
          .predecessor_map(boost::make_iterator_property_map(predecessor.begin(), boost::get(boost::vertex_index, csr))));
  GeodesicField field;
  field.distance.assign(distance.begin(), distance.begin() + static_cast<std::ptrdiff_t>(n));
  field.predecessor.resize(n);
  const double inf = std::numeric_limits<double>::max();
  for (std::size_t c = 0; c < n; ++c) {
    if (distance[c] >= inf) field.distance[c] = std::numeric_limits<double>::infinity();
    const bool reached = std::isfinite(field.distance[c]);
    field.predecessor[c] = (!reached || predecessor[c] == n || predecessor[c] == c) ? -1 : static_cast<std::int64_t>(predecessor[c]);
  }
  return field;
}

}  // namespace treeskel
