#include "treeskel/geodesic.h"

#include "treeskel/error.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <utility>

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
  const std::size_t n = graph.vertex_count();
  const double inf = std::numeric_limits<double>::infinity();
  GeodesicField field;
  field.distance.assign(n, inf);
  field.predecessor.assign(n, -1);
  // Dijkstra on the graph's own arrays, with a binary heap that may hold a cell more than once (a
  // stale entry is skipped when it comes up). Among cells at the same distance the lowest index
  // comes first, and an edge improves a cell only when it makes it strictly nearer: the field does
  // not depend on anything but the graph.
  using Entry = std::pair<double, std::uint32_t>;
  std::vector<Entry> heap;
  heap.reserve(n);
  const auto later = std::greater<Entry>();
  for (auto s : sources) {
    TREESKEL_REQUIRE(s < n, "a root cell is out of range");
    if (field.distance[s] == 0.0) continue;
    field.distance[s] = 0.0;
    heap.emplace_back(0.0, s);
  }
  std::make_heap(heap.begin(), heap.end(), later);
  std::vector<std::uint8_t> done(n, 0);
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), later);
    const auto [d, c] = heap.back();
    heap.pop_back();
    if (done[c]) continue;
    done[c] = 1;
    for (auto e = graph.offsets[c]; e < graph.offsets[c + 1]; ++e) {
      const auto o = graph.targets[e];
      const double through = d + graph.weights[e];
      if (through < field.distance[o]) {
        field.distance[o] = through;
        field.predecessor[o] = c;
        heap.emplace_back(through, o);
        std::push_heap(heap.begin(), heap.end(), later);
      }
    }
  }
  return field;
}

}  // namespace treeskel
