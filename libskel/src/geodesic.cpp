#include "treeskel/geodesic.h"

#include "treeskel/error.h"

#include <algorithm>
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

namespace {

/// The cells waiting in Dijkstra's search, nearest first and, at the same distance, lowest index
/// first: a 4-ary heap that holds each cell once and moves it up when its distance drops.
class CellQueue {
public:
  explicit CellQueue(const std::vector<double>& distance)
      : distance_(distance), where_(distance.size(), kAbsent) {}
  bool empty() const { return heap_.empty(); }
  /// Adds `c`, or moves it up after its distance dropped.
  void push_or_raise(std::uint32_t c) {
    if (where_[c] == kAbsent) {
      where_[c] = static_cast<std::uint32_t>(heap_.size());
      heap_.push_back(c);
    }
    up(where_[c]);
  }
  std::uint32_t pop() {
    const std::uint32_t top = heap_.front();
    where_[top] = kAbsent;
    const std::uint32_t last = heap_.back();
    heap_.pop_back();
    if (!heap_.empty()) {
      heap_.front() = last;
      where_[last] = 0;
      down(0);
    }
    return top;
  }

private:
  static constexpr std::uint32_t kAbsent = ~std::uint32_t{0};
  bool before(std::uint32_t a, std::uint32_t b) const {
    return distance_[a] < distance_[b] || (distance_[a] == distance_[b] && a < b);
  }
  void place(std::size_t i, std::uint32_t c) {
    heap_[i] = c;
    where_[c] = static_cast<std::uint32_t>(i);
  }
  void up(std::size_t i) {
    const std::uint32_t c = heap_[i];
    while (i > 0) {
      const std::size_t parent = (i - 1) / 4;
      if (!before(c, heap_[parent])) break;
      place(i, heap_[parent]);
      i = parent;
    }
    place(i, c);
  }
  void down(std::size_t i) {
    const std::uint32_t c = heap_[i];
    const std::size_t n = heap_.size();
    for (;;) {
      const std::size_t first = 4 * i + 1;
      if (first >= n) break;
      std::size_t best = first;
      for (std::size_t k = first + 1; k < std::min(first + 4, n); ++k)
        if (before(heap_[k], heap_[best])) best = k;
      if (!before(heap_[best], c)) break;
      place(i, heap_[best]);
      i = best;
    }
    place(i, c);
  }

  const std::vector<double>& distance_;
  std::vector<std::uint32_t> where_;  // each cell's place in the heap, or kAbsent
  std::vector<std::uint32_t> heap_;
};

}  // namespace

GeodesicField geodesic_distance(const CellGraph& graph, const std::vector<std::uint32_t>& sources) {
  const std::size_t n = graph.vertex_count();
  const double inf = std::numeric_limits<double>::infinity();
  GeodesicField field;
  field.distance.assign(n, inf);
  field.predecessor.assign(n, -1);
  // Dijkstra on the graph's own arrays. Among cells at the same distance the lowest index comes
  // first, and an edge improves a cell only when it makes it strictly nearer: the field does not
  // depend on anything but the graph.
  CellQueue queue(field.distance);
  for (auto s : sources) {
    TREESKEL_REQUIRE(s < n, "a root cell is out of range");
    if (field.distance[s] == 0.0) continue;
    field.distance[s] = 0.0;
    queue.push_or_raise(s);
  }
  while (!queue.empty()) {
    const std::uint32_t c = queue.pop();
    const double d = field.distance[c];
    for (auto e = graph.offsets[c]; e < graph.offsets[c + 1]; ++e) {
      const auto o = graph.targets[e];
      const double through = d + graph.weights[e];
      // A cell already taken is never improved: the weights are not negative.
      if (through < field.distance[o]) {
        field.distance[o] = through;
        field.predecessor[o] = c;
        queue.push_or_raise(o);
      }
    }
  }
  return field;
}

}  // namespace treeskel
