#include "treeskel/neighbour_graph.h"

#include "treeskel/disjoint_sets.h"
#include "treeskel/error.h"

#include <CGAL/Kd_tree.h>
#include <CGAL/Orthogonal_incremental_neighbor_search.h>
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
using IncrementalSearch = CGAL::Orthogonal_incremental_neighbor_search<Traits>;

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

using CellSets = DisjointSets<std::uint32_t>;

using Adjacency = std::vector<std::vector<std::uint32_t>>;

Adjacency octree_adjacency(const OctreeCells& cells, int reach) {
  Adjacency adj(cells.cell_count());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.cell_count(), 512), [&](const auto& range) {
    for (std::size_t c = range.begin(); c != range.end(); ++c) {
      const Eigen::Vector3i g = cells.coordinates(c);
      for (int dz = -reach; dz <= reach; ++dz)
        for (int dy = -reach; dy <= reach; ++dy)
          for (int dx = -reach; dx <= reach; ++dx) {
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
  CellSets sets(adj.size());
  for (std::size_t c = 0; c < adj.size(); ++c)
    for (auto o : adj[c]) sets.unite(static_cast<std::uint32_t>(c), o);
  std::vector<std::uint32_t> label(adj.size());
  for (std::size_t c = 0; c < adj.size(); ++c) label[c] = sets.find(static_cast<std::uint32_t>(c));
  return label;
}

/// Joins parts of the graph by their shortest links, Kruskal-style over the parts. Parts closer than
/// `near` are joined whatever their size; parts of at least `min_points` points also when they are
/// up to `far` apart (a branch cut off by an occlusion). Each part looks for its nearest foreign cell
/// from up to `probes` of its cells, spread evenly over it, each looking at its nearest few hundred
/// cells at most.
std::size_t bridge_parts(const OctreeCells& cells, Adjacency& adj, double near, double far, std::size_t min_points) {
  const std::size_t probes = 64;
  const std::size_t max_visits = 256;  // a probe deep inside its own part gives up; one near its edge does not
  const auto label = components_of(adj);
  std::vector<std::size_t> part_points(adj.size(), 0), part_cells(adj.size(), 0);
  for (std::size_t c = 0; c < adj.size(); ++c) {
    part_points[label[c]] += cells.point_count(c);
    ++part_cells[label[c]];
  }
  const auto largest = static_cast<std::uint32_t>(
      std::max_element(part_points.begin(), part_points.end()) - part_points.begin());
  if (part_cells[largest] == adj.size()) return 0;

  const MedianIndex index(cells);
  using Link = std::tuple<double, std::uint32_t, std::uint32_t>;
  // Probe cells: every cell of small parts, an even selection of the cells of large ones.
  std::vector<std::uint32_t> probe;
  std::vector<std::size_t> seen(adj.size(), 0);
  for (std::size_t c = 0; c < adj.size(); ++c) {
    const auto l = label[c];
    if (l == largest) continue;
    const std::size_t stride = std::max<std::size_t>(1, part_cells[l] / probes);
    if (seen[l]++ % stride == 0) probe.push_back(static_cast<std::uint32_t>(c));
  }
  std::vector<Link> found(probe.size(), Link{-1.0, 0, 0});
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, probe.size(), 16), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const auto c = probe[i];
      const bool big = part_points[label[c]] >= min_points;
      const double reach = big ? far : near;
      IncrementalSearch search(*index.tree, index.points[c], 0.0, true, IncrementalSearch::Distance(index.map()));
      std::size_t visited = 0;
      for (auto it = search.begin(); it != search.end() && visited++ < max_visits; ++it) {
        const double d = std::sqrt(it->second);
        if (d > reach) break;
        const auto o = it->first;
        if (label[o] == label[c]) continue;
        // A far link must land on a part that is large too: noise does not join across a gap.
        if (d > near && part_points[label[o]] < min_points) continue;
        found[i] = Link{(cells.medians[c] - cells.medians[o]).norm(), c, o};
        break;
      }
    }
  });
  std::vector<Link> links;
  for (const auto& f : found)
    if (std::get<0>(f) >= 0.0) links.push_back(f);
  std::sort(links.begin(), links.end());
  CellSets parts(adj.size());
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

double bridge_distance_for(const NeighbourGraphOptions& options, const OctreeCells& cells) {
  return options.bridge_distance == 0.0 ? 4.0 * cells.cell_size : options.bridge_distance;
}

CellGraph build_neighbour_graph(const OctreeCells& cells, const NeighbourGraphOptions& options) {
  if (options.reach < 1 || options.reach > 3)
    throw OptionError("the octree neighbour reach must be 1, 2 or 3 cells, got " + std::to_string(options.reach));
  Adjacency adj = options.mode == NeighbourMode::knn ? knn_adjacency(cells, options.k) : octree_adjacency(cells, options.reach);
  CellGraph graph;
  const double bridge = bridge_distance_for(options, cells);
  const double far = options.far_bridge_distance == 0.0 ? 0.1 * cells.cube_size : std::max(options.far_bridge_distance, 0.0);
  const auto min_points = static_cast<std::size_t>(options.far_bridge_fraction * static_cast<double>(cells.point_order.size()));
  if (bridge > 0.0) graph.bridges = bridge_parts(cells, adj, bridge, std::max(far, bridge), std::max<std::size_t>(min_points, 10));

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
  CellSets sets(n);
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
