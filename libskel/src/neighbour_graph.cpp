#include "treeskel/neighbour_graph.h"

#include "treeskel/disjoint_sets.h"
#include "treeskel/error.h"
#include "treeskel/kd_search.h"

#include <CGAL/Kd_tree.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <numeric>
#include <queue>
#include <tuple>

namespace treeskel {

namespace {

using kd::KnnSearch;
using kd::Point;
using kd::PointMap;
using kd::Traits;
using kd::Tree;

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

constexpr std::uint64_t kNoKey = ~std::uint64_t{0};  // no Morton key has the top bit

/// Neighbour lists in compressed rows: cell c's are `targets[offsets[c] .. offsets[c+1])`.
struct Adjacency {
  std::vector<std::uint32_t> offsets{0};
  std::vector<std::uint32_t> targets;
  std::size_t size() const { return offsets.size() - 1; }
  const std::uint32_t* begin(std::size_t c) const { return targets.data() + offsets[c]; }
  const std::uint32_t* end(std::size_t c) const { return targets.data() + offsets[c + 1]; }
};

/// The cells by Morton key in an open-addressing hash table: a lookup takes a probe or two where a
/// binary search of the sorted keys took about seventeen.
class KeyTable {
public:
  explicit KeyTable(const std::vector<std::uint64_t>& keys) {
    int bits = 4;
    while ((std::size_t{1} << bits) < 2 * keys.size()) ++bits;
    shift_ = 64 - bits;
    mask_ = (std::size_t{1} << bits) - 1;
    slots_.assign(mask_ + 1, Slot{kNoKey, 0});
    for (std::size_t i = 0; i < keys.size(); ++i) {
      std::size_t s = slot(keys[i]);
      while (slots_[s].key != kNoKey) s = (s + 1) & mask_;
      slots_[s] = Slot{keys[i], static_cast<std::uint32_t>(i)};
    }
  }
  /// The cell with this key, or -1.
  std::int64_t find(std::uint64_t key) const {
    for (std::size_t s = slot(key);; s = (s + 1) & mask_) {
      if (slots_[s].key == key) return slots_[s].cell;
      if (slots_[s].key == kNoKey) return -1;
    }
  }

private:
  struct Slot {
    std::uint64_t key;
    std::uint32_t cell;
  };
  std::size_t slot(std::uint64_t key) const { return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ULL) >> shift_); }
  std::vector<Slot> slots_;
  std::size_t mask_ = 0;
  int shift_ = 60;
};

/// The cells nearest a cell's median, nearest first, with no tree to build: the cells sorted by Morton
/// key form blocks of 4 x 4 x 4 cells as runs, found by a hash of the block keys. Blocks are read
/// shell by shell around the starting cell's block, and a cell is handed out once no block still
/// unread can hold a nearer median (a median lies in its cell's box). Equal distances go by cell index.
class NearestCells {
public:
  explicit NearestCells(const OctreeCells& cells)
      : cells_(cells), levels_(std::min(2, cells.depth)), table_(block_keys(cells, levels_, first_)),
        side_(1 << (cells.depth - levels_)), size_(cells.cell_size * static_cast<double>(1 << levels_)) {}

  /// Calls `visit(cell, distance)` for the cells whose medians lie within `reach` of `from`'s, nearest
  /// first (`from` itself first), until it returns false.
  template <class Visit>
  void visit(std::uint32_t from, double reach, Visit&& visit) const {
    const Eigen::Vector3d& centre = cells_.medians[from];
    const Eigen::Vector3i home = morton_decode(cells_.keys[from] >> (3 * levels_));
    using Entry = std::pair<double, std::uint32_t>;  // squared distance, cell
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> pending;
    const double reach2 = reach * reach;
    for (int r = 0;; ++r) {
      bool any_inside = false;  // a block of this shell lies in the grid
      const auto read = [&](int x, int y, int z) {
        if (x < 0 || y < 0 || z < 0 || x >= side_ || y >= side_ || z >= side_) return;
        any_inside = true;
        const auto b = table_.find(morton_encode(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y),
                                                 static_cast<std::uint32_t>(z)));
        if (b < 0) return;
        for (std::uint32_t c = first_[static_cast<std::size_t>(b)]; c < first_[static_cast<std::size_t>(b) + 1]; ++c) {
          const double d2 = (cells_.medians[c] - centre).squaredNorm();
          if (d2 <= reach2) pending.emplace(d2, c);
        }
      };
      for (int dz = -r; dz <= r; ++dz)
        for (int dy = -r; dy <= r; ++dy) {
          const bool face = std::abs(dz) == r || std::abs(dy) == r;
          for (int dx = -r; dx <= r; dx += face ? 1 : 2 * r)  // off the y and z faces, the two x faces only
            read(home.x() + dx, home.y() + dy, home.z() + dz);
        }
      // Every block not read yet is r + 1 blocks away or more: its medians are at least r blocks off.
      const double bound = static_cast<double>(r) * size_ * (1.0 - 1e-9);
      const bool last = !any_inside || bound > reach;
      while (!pending.empty() && (last || pending.top().first < bound * bound)) {
        const auto [d2, c] = pending.top();
        pending.pop();
        if (!visit(c, std::sqrt(d2))) return;
      }
      if (last) return;
    }
  }

private:
  static KeyTable block_keys(const OctreeCells& cells, int levels, std::vector<std::uint32_t>& first) {
    std::vector<std::uint64_t> keys;
    for (std::size_t c = 0; c < cells.cell_count(); ++c) {
      const std::uint64_t key = cells.keys[c] >> (3 * levels);
      if (keys.empty() || keys.back() != key) {
        keys.push_back(key);
        first.push_back(static_cast<std::uint32_t>(c));
      }
    }
    first.push_back(static_cast<std::uint32_t>(cells.cell_count()));
    return KeyTable(keys);
  }

  const OctreeCells& cells_;
  int levels_;
  std::vector<std::uint32_t> first_;  // block b's cells: first_[b] .. first_[b + 1]
  KeyTable table_;
  int side_;
  double size_;
};

/// Compressed rows from `blocks`, runs of consecutive rows in cell order, and `counts`, the length
/// of each row.
Adjacency concatenate(const std::vector<std::vector<std::uint32_t>>& blocks, const std::vector<std::uint32_t>& counts) {
  Adjacency adj;
  adj.offsets.resize(counts.size() + 1);
  adj.offsets[0] = 0;
  for (std::size_t c = 0; c < counts.size(); ++c) adj.offsets[c + 1] = adj.offsets[c] + counts[c];
  adj.targets.reserve(adj.offsets.back());
  for (const auto& b : blocks) adj.targets.insert(adj.targets.end(), b.begin(), b.end());
  return adj;
}

/// Compressed rows for `n` cells, filled side by side in blocks of cells: `fill(c, row, scratch)`
/// appends the neighbours of cell c to the empty `row` in ascending order; `scratch` is a `Scratch`
/// kept per block of cells.
template <class Scratch, class Fill>
Adjacency rows_in_blocks(std::size_t n, Fill fill) {
  constexpr std::size_t block = 2048;
  std::vector<std::vector<std::uint32_t>> blocks((n + block - 1) / block);
  std::vector<std::uint32_t> counts(n, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size(), 1), [&](const auto& range) {
    Scratch scratch;
    std::vector<std::uint32_t> row;
    for (std::size_t b = range.begin(); b != range.end(); ++b) {
      auto& out = blocks[b];
      for (std::size_t c = b * block; c < std::min(n, (b + 1) * block); ++c) {
        row.clear();
        fill(c, row, scratch);
        counts[c] = static_cast<std::uint32_t>(row.size());
        out.insert(out.end(), row.begin(), row.end());
      }
    }
  });
  return concatenate(blocks, counts);
}

Adjacency octree_adjacency(const OctreeCells& cells, int reach) {
  const KeyTable table(cells.keys);
  const int side = 1 << cells.depth;
  struct Along {
    std::vector<std::uint64_t> axis[3];  // per axis: the spread bits of each offset's coordinate (or none)
  };
  return rows_in_blocks<Along>(cells.cell_count(), [&](std::size_t c, std::vector<std::uint32_t>& row, Along& along) {
    const Eigen::Vector3i g = cells.coordinates(c);
    for (int a = 0; a < 3; ++a) {
      along.axis[a].clear();
      for (int d = -reach; d <= reach; ++d) {
        const int x = g[a] + d;
        const bool inside = x >= 0 && x < side;
        const auto u = static_cast<std::uint32_t>(inside ? x : 0);
        along.axis[a].push_back(inside ? morton_encode(a == 0 ? u : 0, a == 1 ? u : 0, a == 2 ? u : 0) : kNoKey);
      }
    }
    const std::size_t width = along.axis[0].size();
    for (std::size_t k = 0; k < width; ++k)
      for (std::size_t j = 0; j < width; ++j)
        for (std::size_t i = 0; i < width; ++i) {
          const std::uint64_t x = along.axis[0][i], y = along.axis[1][j], z = along.axis[2][k];
          if (x == kNoKey || y == kNoKey || z == kNoKey) continue;
          const std::uint64_t key = x | y | z;
          if (key == cells.keys[c]) continue;
          const auto other = table.find(key);
          if (other >= 0) row.push_back(static_cast<std::uint32_t>(other));
        }
    std::sort(row.begin(), row.end());
  });
}

/// `adj` with the cells where the points are sparse for the grid (on average fewer than `occupancy`
/// points a cell over the cell and its neighbours in `adj`) also neighbours of such cells two cells
/// apart along some axis (NeighbourGraphOptions::sparse_occupancy).
Adjacency widen_sparse(const OctreeCells& cells, const Adjacency& adj, double occupancy) {
  const std::size_t n = cells.cell_count();
  std::vector<char> sparse(n, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
    for (std::size_t c = range.begin(); c != range.end(); ++c) {
      std::size_t points = cells.point_count(c);
      for (const std::uint32_t* o = adj.begin(c); o != adj.end(c); ++o) points += cells.point_count(*o);
      sparse[c] = static_cast<double>(points) < occupancy * static_cast<double>(adj.end(c) - adj.begin(c) + 1);
    }
  });
  const KeyTable table(cells.keys);
  const int side = 1 << cells.depth;
  struct None {};
  return rows_in_blocks<None>(n, [&](std::size_t c, std::vector<std::uint32_t>& row, None&) {
    row.assign(adj.begin(c), adj.end(c));
    if (!sparse[c]) return;
    const Eigen::Vector3i g = cells.coordinates(c);
    for (int z = -2; z <= 2; ++z)
      for (int y = -2; y <= 2; ++y)
        for (int x = -2; x <= 2; ++x) {
          if (std::max({std::abs(x), std::abs(y), std::abs(z)}) != 2) continue;
          const Eigen::Vector3i h = g + Eigen::Vector3i(x, y, z);
          if ((h.array() < 0).any() || (h.array() >= side).any()) continue;
          const auto other = table.find(morton_encode(h.x(), h.y(), h.z()));
          if (other >= 0 && sparse[static_cast<std::size_t>(other)]) row.push_back(static_cast<std::uint32_t>(other));
        }
    std::sort(row.begin(), row.end());
  });
}

Adjacency knn_adjacency(const OctreeCells& cells, int k) {
  if (k < 1) throw OptionError("k for the nearest-neighbour graph must be at least 1, got " + std::to_string(k));
  const MedianIndex index(cells);
  std::vector<std::vector<std::uint32_t>> adj(cells.cell_count());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.cell_count(), 512), [&](const auto& range) {
    for (std::size_t c = range.begin(); c != range.end(); ++c) {
      KnnSearch search(*index.tree, index.points[c], static_cast<unsigned>(k + 1), 0, true,
                       KnnSearch::Distance(index.map()));
      for (const auto& hit : search)
        if (hit.first != c) adj[c].push_back(hit.first);
    }
  });
  std::vector<std::vector<std::uint32_t>> sym(cells.cell_count());
  for (std::size_t c = 0; c < adj.size(); ++c)
    for (auto o : adj[c]) {
      sym[c].push_back(o);
      sym[o].push_back(static_cast<std::uint32_t>(c));
    }
  std::vector<std::uint32_t> counts(sym.size());
  for (std::size_t c = 0; c < sym.size(); ++c) {
    auto& list = sym[c];
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    counts[c] = static_cast<std::uint32_t>(list.size());
  }
  return concatenate(sym, counts);
}

std::vector<std::uint32_t> components_of(const Adjacency& adj) {
  CellSets sets(adj.size());
  for (std::size_t c = 0; c < adj.size(); ++c)
    for (const std::uint32_t* o = adj.begin(c); o != adj.end(c); ++o) sets.unite(static_cast<std::uint32_t>(c), *o);
  std::vector<std::uint32_t> label(adj.size());
  for (std::size_t c = 0; c < adj.size(); ++c) label[c] = sets.find(static_cast<std::uint32_t>(c));
  return label;
}

/// Joins parts of the graph by their shortest links, Kruskal-style over the parts. Parts closer than
/// `near` are joined whatever their size; parts of at least `min_points` points also when they are
/// up to `far` apart (a branch cut off by an occlusion). Each part looks for its nearest foreign cell
/// from up to `probes` of its cells spread evenly over it, and as many over its rim, each looking at
/// its nearest few hundred cells at most. That runs in rounds, up to `rounds`: in each, the parts not
/// joined to the largest yet look again, the parts joined so far counting as one. Returns the links,
/// each once, in the order they were chosen.
std::vector<std::pair<std::uint32_t, std::uint32_t>> bridge_parts(const OctreeCells& cells, const Adjacency& adj, double near,
                                                                  double far, std::size_t min_points, std::size_t rounds) {
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
  if (part_cells[largest] == adj.size()) return {};

  const NearestCells nearest(cells);
  using Link = std::tuple<double, std::uint32_t, std::uint32_t>;
  // Probe cells: every cell of a small part; of a large one, an even selection of its cells (as
  // before, so that no link those found is lost) and another of the quarter of its cells with the
  // fewest neighbours: its rim, where a gap cut it off. (Spread over all its cells alone, the probes
  // of a piece of 1,848 cells lay deep inside it and met their 256 cells before any other part: the
  // benchmark's tree6_missing_2 left 5,014 of its points out.)
  std::vector<std::uint32_t> probe;
  // Whether the next of the `count` items of group `key` is one of `probes` spread evenly over them.
  std::vector<std::size_t> seen(adj.size(), 0);
  const auto spread = [&](std::size_t key, std::size_t count) { return seen[key]++ % std::max<std::size_t>(1, count / probes) == 0; };
  std::vector<std::tuple<std::uint32_t, std::size_t, std::uint32_t>> large;  // (part, neighbours, cell)
  for (std::size_t c = 0; c < adj.size(); ++c) {
    const auto l = label[c];
    if (l == largest) continue;
    const auto cell = static_cast<std::uint32_t>(c);
    if (part_cells[l] > probes) large.emplace_back(l, static_cast<std::size_t>(adj.end(c) - adj.begin(c)), cell);
    if (spread(l, part_cells[l])) probe.push_back(cell);
  }
  std::sort(large.begin(), large.end());
  std::vector<std::uint32_t> rim;
  for (std::size_t i = 0, j = 0; i < large.size(); i = j) {
    while (j < large.size() && std::get<0>(large[j]) == std::get<0>(large[i])) ++j;
    rim.clear();
    for (std::size_t k = i; k < i + std::max(probes, (j - i) / 4); ++k) rim.push_back(std::get<2>(large[k]));
    std::sort(rim.begin(), rim.end());
    const std::size_t stride = std::max<std::size_t>(1, rim.size() / probes);
    for (std::size_t k = 0; k < rim.size(); k += stride) probe.push_back(rim[k]);
  }
  CellSets parts(adj.size());
  std::vector<std::pair<std::uint32_t, std::uint32_t>> added;
  std::vector<std::uint32_t> group(adj.size());  // per part: the parts joined so far that it is in
  std::iota(group.begin(), group.end(), 0u);
  const auto parts_of = [&](std::uint32_t cell) { return group[label[cell]]; };
  // A probe stops at the first foreign cell it meets. Where an occlusion cut a crown into pieces
  // nearer one another than the tree, that was always another piece, and the pieces joined one
  // another but never the tree (the benchmark's tree2_missing_2 left 45% of its points out). So the
  // probes that found a link look again, their part and the parts joined to it now one, until they
  // are joined to the largest part. A probe that found none will not: what is foreign to it only
  // shrinks.
  std::vector<std::uint32_t> active = std::move(probe);
  for (std::size_t round = 0; round < rounds && !active.empty(); ++round) {
    std::vector<Link> found(active.size(), Link{-1.0, 0, 0});
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, active.size(), 16), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        const auto c = active[i];
        const bool big = part_points[label[c]] >= min_points;
        std::size_t visited = 0;
        nearest.visit(c, big ? far : near, [&](std::uint32_t o, double d) {
          if (visited++ >= max_visits) return false;
          if (parts_of(o) == parts_of(c)) return true;
          // A far link must land on a part that is large too: noise does not join across a gap.
          if (d > near && part_points[label[o]] < min_points) return true;
          found[i] = Link{(cells.medians[c] - cells.medians[o]).norm(), c, o};
          return false;
        });
      }
    });
    std::vector<Link> links;
    for (const auto& f : found)
      if (std::get<0>(f) >= 0.0) links.push_back(f);
    std::sort(links.begin(), links.end());
    for (const auto& [d, a, b] : links)
      if (parts.unite(label[a], label[b])) added.emplace_back(a, b);
    for (std::size_t l = 0; l < adj.size(); ++l) group[l] = parts.find(static_cast<std::uint32_t>(l));
    // At most `probes` of each group look again, spread evenly over its probes.
    std::vector<std::uint32_t> again;
    std::vector<std::size_t> count(adj.size(), 0);
    for (std::size_t i = 0; i < active.size(); ++i)
      if (std::get<0>(found[i]) >= 0.0 && parts_of(active[i]) != group[largest]) {
        again.push_back(active[i]);
        ++count[parts_of(active[i])];
      }
    std::fill(seen.begin(), seen.end(), 0);
    active.clear();
    for (std::uint32_t c : again)
      if (spread(parts_of(c), count[parts_of(c)])) active.push_back(c);
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
  if (options.mode == NeighbourMode::octree && options.reach == 1 && cells.cube_scale > 1.0 && options.sparse_occupancy > 0.0)
    adj = widen_sparse(cells, adj, options.sparse_occupancy);
  CellGraph graph;
  const double bridge = bridge_distance_for(options, cells);
  const double far = options.far_bridge_distance == 0.0 ? 0.1 * cells.cube_size / cells.cube_scale : std::max(options.far_bridge_distance, 0.0);
  const auto min_points = std::max(options.far_bridge_min_points,
                                   static_cast<std::size_t>(options.far_bridge_fraction * static_cast<double>(cells.point_order.size())));
  std::vector<std::pair<std::uint32_t, std::uint32_t>> links;
  if (bridge > 0.0)
    links = bridge_parts(cells, adj, bridge, std::max(far, bridge), min_points, std::max<std::size_t>(options.bridge_rounds, 1));
  graph.bridges = links.size();

  const std::size_t n = adj.size();
  if (links.empty()) {
    graph.offsets = std::move(adj.offsets);
    graph.targets = std::move(adj.targets);
  } else {
    // Each cell's bridges follow its neighbours, in the order they were chosen.
    std::vector<std::vector<std::uint32_t>> extra(n);
    for (const auto& [a, b] : links) {
      extra[a].push_back(b);
      extra[b].push_back(a);
    }
    graph.offsets.assign(1, 0);
    graph.offsets.reserve(n + 1);
    graph.targets.reserve(adj.targets.size() + 2 * links.size());
    for (std::size_t c = 0; c < n; ++c) {
      graph.targets.insert(graph.targets.end(), adj.begin(c), adj.end(c));
      graph.targets.insert(graph.targets.end(), extra[c].begin(), extra[c].end());
      graph.offsets.push_back(static_cast<std::uint32_t>(graph.targets.size()));
    }
  }
  const double shortest = 1e-9 * cells.cell_size;  // keeps Dijkstra's weights positive
  graph.weights.resize(graph.targets.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
    for (std::size_t c = range.begin(); c != range.end(); ++c)
      for (auto e = graph.offsets[c]; e < graph.offsets[c + 1]; ++e)
        graph.weights[e] = std::max((cells.medians[c] - cells.medians[graph.targets[e]]).norm(), shortest);
  });
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
