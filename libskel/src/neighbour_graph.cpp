#include "treeskel/neighbour_graph.h"

#include "treeskel/error.h"

#include <CGAL/Fuzzy_sphere.h>
#include <CGAL/Kd_tree.h>
#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/property_map.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <numeric>
#include <tuple>

namespace treeskel {

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using PointMap = CGAL::Pointer_property_map<Point>::type;
using Traits = CGAL::Search_traits_adapter<std::uint32_t, PointMap, CGAL::Search_traits_3<Kernel>>;
using KnnSearch = CGAL::Orthogonal_k_neighbor_search<Traits>;
using Tree = KnnSearch::Tree;
using Sphere = CGAL::Fuzzy_sphere<Traits>;

/// Kd-tree over the cell medians, indexed by cell id.
struct MedianIndex {
  std::vector<Point> points;
  std::unique_ptr<Tree> tree;
  explicit MedianIndex(const OctreeCells& cells) {
    points.reserve(cells.cell_count());
    for (const auto& m : cells.medians) points.emplace_back(m.x(), m.y(), m.z());
    std::vector<std::uint32_t> ids(points.size());
    std::iota(ids.begin(), ids.end(), 0u);
    tree = std::make_unique<Tree>(ids.begin(), ids.end(), Tree::Splitter(), Traits(PointMap(points.data())));
    tree->build();
  }
  PointMap map() const { return PointMap(const_cast<Point*>(points.data())); }
};

class DisjointSets {
public:
  explicit DisjointSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0u); }
  std::uint32_t find(std::uint32_t v) {
    while (parent_[v] != v) v = parent_[v] = parent_[parent_[v]];
    return v;
  }
  bool unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    if (b < a) std::swap(a, b);
    parent_[b] = a;
    return true;
  }

private:
  std::vector<std::uint32_t> parent_;
};

using Adjacency = std::vector<std::vector<std::uint32_t>>;

Adjacency octree_adjacency(const OctreeCells& cells) {
  Adjacency adj(cells.cell_count());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.cell_count(), 512), [&](const auto& range) {
    for (std::size_t c = range.begin(); c != range.end(); ++c) {
      const Eigen::Vector3i g = cells.coordinates(c);
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            if (dx == 0 && dy == 0 && dz == 0) continue;
            const auto other = cells.find(g + Eigen::Vector3i(dx, dy, dz));
            if (other >= 0) adj[c].push_back(static_cast<std::uint32_t>(other));
          }
      std::sort(adj[c].begin(), adj[c].end());
    }
  });
  return adj;
}

Adjacency knn_adjacency(const OctreeCells& cells, int k) {
  if (k < 1) throw OptionError("k for the nearest-neighbour graph must be at least 1, got " + std::to_string(k));
  const MedianIndex index(cells);
  Adjacency adj(cells.cell_count());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.cell_count(), 512), [&](const auto& range) {
    for (std::size_t c = range.begin(); c != range.end(); ++c) {
      KnnSearch search(*index.tree, index.points[c], static_cast<unsigned>(k + 1), 0, true,
                       KnnSearch::Distance(index.map()));
      for (const auto& hit : search)
        if (hit.first != c) adj[c].push_back(hit.first);
    }
  });
  Adjacency sym(cells.cell_count());
  for (std::size_t c = 0; c < adj.size(); ++c)
    for (auto o : adj[c]) {
      sym[c].push_back(o);
      sym[o].push_back(static_cast<std::uint32_t>(c));
    }
  for (auto& list : sym) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return sym;
}

std::vector<std::uint32_t> components_of(const Adjacency& adj) {
  DisjointSets sets(adj.size());
  for (std::size_t c = 0; c < adj.size(); ++c)
    for (auto o : adj[c]) sets.unite(static_cast<std::uint32_t>(c), o);
  std::vector<std::uint32_t> label(adj.size());
  for (std::size_t c = 0; c < adj.size(); ++c) label[c] = sets.find(static_cast<std::uint32_t>(c));
  return label;
}

/// Joins parts closer than `distance` by their shortest links, Kruskal-style over the parts.
std::size_t bridge_parts(const OctreeCells& cells, Adjacency& adj, double distance) {
  const auto label = components_of(adj);
  std::vector<std::size_t> part_points(adj.size(), 0);
  for (std::size_t c = 0; c < adj.size(); ++c) part_points[label[c]] += cells.point_count(c);
  const auto largest = static_cast<std::uint32_t>(
      std::max_element(part_points.begin(), part_points.end()) - part_points.begin());
  if (std::count_if(label.begin(), label.end(), [&](auto l) { return l != largest; }) == 0) return 0;

  const MedianIndex index(cells);
  using Link = std::tuple<double, std::uint32_t, std::uint32_t>;
  std::vector<std::vector<Link>> found(adj.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, adj.size(), 256), [&](const auto& range) {
    std::vector<std::uint32_t> hits;
    for (std::size_t c = range.begin(); c != range.end(); ++c) {
      if (label[c] == largest) continue;
      hits.clear();
      index.tree->search(std::back_inserter(hits), Sphere(index.points[c], distance, 0.0, Traits(index.map())));
      for (auto o : hits) {
        if (label[o] == label[c]) continue;
        const double d = (cells.medians[c] - cells.medians[o]).norm();
        if (d <= distance) found[c].emplace_back(d, static_cast<std::uint32_t>(c), o);
      }
    }
  });
  std::vector<Link> links;
  for (auto& f : found) links.insert(links.end(), f.begin(), f.end());
  std::sort(links.begin(), links.end());
  DisjointSets parts(adj.size());
  std::size_t added = 0;
  for (const auto& [d, a, b] : links) {
    if (!parts.unite(label[a], label[b])) continue;
    adj[a].push_back(b);
    adj[b].push_back(a);
    ++added;
  }
  return added;
}

}  // namespace

CellGraph build_neighbour_graph(const OctreeCells& cells, const NeighbourGraphOptions& options) {
  Adjacency adj = options.mode == NeighbourMode::knn ? knn_adjacency(cells, options.k) : octree_adjacency(cells);
  CellGraph graph;
  const double bridge = options.bridge_distance == 0.0 ? 4.0 * cells.cell_size : options.bridge_distance;
  if (bridge > 0.0) graph.bridges = bridge_parts(cells, adj, bridge);

  const double shortest = 1e-9 * cells.cell_size;  // keeps Dijkstra's weights positive
  graph.offsets.reserve(adj.size() + 1);
  graph.offsets.push_back(0);
  for (std::size_t c = 0; c < adj.size(); ++c) {
    for (auto o : adj[c]) {
      graph.targets.push_back(o);
      graph.weights.push_back(std::max((cells.medians[c] - cells.medians[o]).norm(), shortest));
    }
    graph.offsets.push_back(static_cast<std::uint32_t>(graph.targets.size()));
  }
  return graph;
}

std::vector<std::uint32_t> connected_components(const CellGraph& graph, std::uint32_t* count) {
  const std::size_t n = graph.vertex_count();
  DisjointSets sets(n);
  for (std::size_t c = 0; c < n; ++c)
    for (auto e = graph.offsets[c]; e < graph.offsets[c + 1]; ++e) sets.unite(static_cast<std::uint32_t>(c), graph.targets[e]);
  std::vector<std::uint32_t> id(n), renumber(n, UINT32_MAX);
  std::uint32_t next = 0;
  for (std::size_t c = 0; c < n; ++c) {
    const auto root = sets.find(static_cast<std::uint32_t>(c));
    if (renumber[root] == UINT32_MAX) renumber[root] = next++;
    id[c] = renumber[root];
  }
  if (count) *count = next;
  return id;
}

MainPart select_main_part(const OctreeCells& cells, const CellGraph& graph, const NeighbourGraphOptions& options) {
  std::uint32_t parts = 0;
  const auto id = connected_components(graph, &parts);
  std::vector<std::size_t> points(parts, 0);
  for (std::size_t c = 0; c < id.size(); ++c) points[id[c]] += cells.point_count(c);
  const auto main = static_cast<std::uint32_t>(std::max_element(points.begin(), points.end()) - points.begin());
  MainPart result;
  result.parts = parts;
  result.in_tree.resize(id.size());
  for (std::size_t c = 0; c < id.size(); ++c) result.in_tree[c] = id[c] == main;
  const double total = static_cast<double>(cells.point_order.size());
  for (std::uint32_t p = 0; p < parts; ++p) {
    if (p == main) continue;
    if (static_cast<double>(points[p]) < options.small_cluster_fraction * total)
      result.left_out.small_clusters += points[p];
    else
      result.left_out.far_parts += points[p];
  }
  return result;
}

}  // namespace treeskel
