#include "treeskel/complete.h"

#include "treeskel/disjoint_sets.h"
#include "treeskel/error.h"
#include "treeskel/geometry.h"
#include "treeskel/kd_search.h"
#include "treeskel/l1_median.h"
#include "treeskel/level_sets.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>
#include <unordered_map>
#include <unordered_set>

namespace treeskel {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

/// How far `p` lies outside the tube of the edge a-b (its radii interpolated along it).
double outside_edge(const Skeleton& skeleton, const Eigen::Vector3d& p, NodeId a, NodeId b) {
  return outside_tube(p, skeleton[a].position, skeleton[b].position, skeleton[a].radius, skeleton[b].radius);
}

/// Every skeleton edge sampled at a fixed spacing, in a kd-tree: the edges near a point.
class EdgeIndex {
public:
  EdgeIndex(const Skeleton& skeleton, double spacing) {
    for (auto [e, end] = boost::edges(skeleton.graph); e != end; ++e) {
      const NodeId a = boost::source(*e, skeleton.graph), b = boost::target(*e, skeleton.graph);
      const Eigen::Vector3d pa = skeleton[a].position, pb = skeleton[b].position;
      const int steps = std::max(1, static_cast<int>(std::ceil((pb - pa).norm() / spacing)));
      for (int s = 0; s <= steps; ++s) {
        const Eigen::Vector3d q = pa + (pb - pa) * (static_cast<double>(s) / steps);
        samples_.emplace_back(q.x(), q.y(), q.z());
        edges_.emplace_back(a, b);
      }
    }
    std::vector<std::uint32_t> ids(samples_.size());
    std::iota(ids.begin(), ids.end(), 0u);
    tree_ = std::make_unique<Tree>(ids.begin(), ids.end(), Tree::Splitter(), Traits(PointMap(samples_.data())));
    tree_->build();
  }

  /// The node nearest to `p` among the ends of the edges near it.
  NodeId nearest_node(const Skeleton& skeleton, const Eigen::Vector3d& p) const {
    NodeId best = 0;
    double best_d = std::numeric_limits<double>::infinity();
    for (const auto& [id, d2] : near_samples(p))
      for (NodeId v : {edges_[id].first, edges_[id].second}) {
        const double d = (skeleton[v].position - p).norm();
        if (d < best_d || (d == best_d && v < best)) {
          best_d = d;
          best = v;
        }
      }
    return best;
  }

  /// The least distance outside the tubes of the edges near `p`.
  double outside(const Skeleton& skeleton, const Eigen::Vector3d& p) const {
    if (samples_.empty()) return std::numeric_limits<double>::infinity();
    double best = std::numeric_limits<double>::infinity();
    for (const auto& [id, d2] : near_samples(p)) best = std::min(best, outside_edge(skeleton, p, edges_[id].first, edges_[id].second));
    return best;
  }

private:
  using Point = kd::Point;
  using PointMap = kd::PointMap;
  using Traits = kd::Traits;
  using KnnSearch = kd::KnnSearch;
  using Distance = KnnSearch::Distance;
  using Tree = kd::Tree;

  /// The 8 edge samples nearest to `p`.
  KnnSearch near_samples(const Eigen::Vector3d& p) const {
    return KnnSearch(*tree_, Point(p.x(), p.y(), p.z()), 8, 0.0, true, Distance(PointMap(const_cast<Point*>(samples_.data()))));
  }

  std::vector<Point> samples_;
  std::vector<std::pair<NodeId, NodeId>> edges_;
  std::unique_ptr<Tree> tree_;
};

/// Integer grid key of a position for cells of side `size`.
std::uint64_t grid_key(const Eigen::Vector3d& p, double size, int dx = 0, int dy = 0, int dz = 0) {
  auto axis = [&](double v, int d) {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v / size)) + d + (1 << 20)) & 0x1fffffu;
  };
  return axis(p.x(), dx) | (axis(p.y(), dy) << 21) | (axis(p.z(), dz) << 42);
}

/// Calls `visit(key)` for the grid cell of `p` and its 26 neighbours.
template <class Visit>
void for_cells_around(const Eigen::Vector3d& p, double size, Visit&& visit) {
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz) visit(grid_key(p, size, dx, dy, dz));
}

}  // namespace

CompleteOptions all_grafts() {
  CompleteOptions o;
  o.tufts_and_bushes = true;
  return o;
}

CompleteStats complete_skeleton(Skeleton& skeleton, const PointCloud& cloud, double cell_size, const CompleteOptions& options) {
  TREESKEL_REQUIRE(cell_size > 0.0, "the cell size must be positive");
  CompleteStats stats;
  const double margin = options.margin > 0.0 ? options.margin : cell_size;
  const double link = options.link > 0.0 ? options.link : 2.0 * cell_size;
  const double min_reach = options.min_reach > 0.0 ? options.min_reach : margin + link;
  // A path's step is at most `link` long, so with bands at least that wide a component's predecessor
  // lies in its own band or the one below: narrower bands let paths skip a band, and one twig became
  // two interleaved chains.
  const double band = std::max(options.band_width, link);
  const std::size_t n = cloud.size();
  const std::size_t nodes_before = skeleton.node_count();

  std::vector<std::uint32_t> owner(n, kNone);
  for (NodeId v = 0; v < nodes_before; ++v)
    for (auto p : skeleton[v].points) owner[p] = static_cast<std::uint32_t>(v);

  // 1. Uncovered points: outside every tube near them by more than the margin. The edges at a point's
  // own node decide most; the kd-tree of edge samples settles the rest.
  std::vector<double> outside(n, 0.0);  // how far outside the tubes an uncovered point lies; 0: covered
  const EdgeIndex index(skeleton, std::max(cell_size * 0.5, 1e-12));
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nodes_before, 64), [&](const auto& range) {
    for (std::size_t v = range.begin(); v != range.end(); ++v) {
      const auto& node = skeleton[v];
      for (auto p : node.points) {
        const Eigen::Vector3d& x = cloud.positions[p];
        double out = (x - node.position).norm() - node.radius;
        for (auto [a, end] = boost::adjacent_vertices(v, skeleton.graph); a != end && out > margin; ++a)
          out = std::min(out, outside_edge(skeleton, x, v, *a));
        if (out > margin) out = std::min(out, index.outside(skeleton, x));
        if (out > margin) outside[p] = out;
      }
    }
  });
  std::vector<std::uint32_t> lost;  // the uncovered points, in index order
  for (std::size_t p = 0; p < n; ++p)
    if (outside[p] > 0.0) lost.push_back(static_cast<std::uint32_t>(p));
  stats.uncovered_points = lost.size();
  if (lost.empty()) return stats;

  // 2. Neighbours within `link`: a grid of the uncovered points, searched around each of them and
  // around every covered point that lies in a grid cell next to one.
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;  // key -> positions in `lost`
  for (std::uint32_t i = 0; i < lost.size(); ++i) grid[grid_key(cloud.positions[lost[i]], link)].push_back(i);
  auto for_near = [&](const Eigen::Vector3d& x, auto&& visit) {
    for_cells_around(x, link, [&](std::uint64_t key) {
      const auto it = grid.find(key);
      if (it == grid.end()) return;
      for (auto j : it->second) {
        const double d = (cloud.positions[lost[j]] - x).norm();
        if (d <= link) visit(j, d);
      }
    });
  };
  const std::size_t m = lost.size();
  std::vector<std::vector<std::pair<std::uint32_t, double>>> near(m);
  for (std::uint32_t i = 0; i < m; ++i)
    for_near(cloud.positions[lost[i]], [&](std::uint32_t j, double d) {
      if (j != i && d > 0.0) near[i].emplace_back(j, d);  // repeats of one place are no step
    });
  // Seeds: the shortest step from a covered point. `seed_owner` is the node that holds the covered
  // point a path starts from: it marks the seeded points and breaks ties between equal paths (the
  // graft itself hangs from the node nearest to it, see step 5).
  std::vector<double> dist(m, std::numeric_limits<double>::infinity());
  std::vector<std::uint32_t> seed_owner(m, kNone), pred(m, kNone);
  std::unordered_set<std::uint64_t> near_keys;
  for (const auto& [key, members] : grid)
    for_cells_around(cloud.positions[lost[members.front()]], link, [&](std::uint64_t k) { near_keys.insert(k); });
  for (std::size_t p = 0; p < n; ++p) {
    if (outside[p] > 0.0 || owner[p] == kNone) continue;
    const Eigen::Vector3d& x = cloud.positions[p];
    if (!near_keys.count(grid_key(x, link))) continue;
    for_near(x, [&](std::uint32_t j, double d) {
      if (d < dist[j] || (d == dist[j] && owner[p] < seed_owner[j])) {
        dist[j] = d;
        seed_owner[j] = owner[p];
      }
    });
  }

  // 3. Shortest paths from the covered points over the uncovered ones.
  using Item = std::pair<double, std::uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  for (std::uint32_t i = 0; i < m; ++i)
    if (seed_owner[i] != kNone) queue.emplace(dist[i], i);
  std::vector<char> done(m, 0);
  while (!queue.empty()) {
    const auto [d, i] = queue.top();
    queue.pop();
    if (done[i]) continue;
    done[i] = 1;
    for (const auto& [j, w] : near[i]) {
      const double nd = d + w;
      if (!done[j] && (nd < dist[j] || (nd == dist[j] && seed_owner[i] < seed_owner[j]))) {
        dist[j] = nd;
        seed_owner[j] = seed_owner[i];
        pred[j] = i;
        queue.emplace(nd, j);
      }
    }
  }

  // 4. Level sets of the path length: components of the edges inside one band, each hanging from the
  // component of its lowest point's predecessor, or from the node its path starts at.
  std::vector<std::int64_t> level(m, -1);
  for (std::uint32_t i = 0; i < m; ++i)
    if (done[i]) level[i] = static_cast<std::int64_t>(std::floor(dist[i] / band));
  DisjointSets<std::uint32_t> sets(m);
  for (std::uint32_t i = 0; i < m; ++i)
    if (level[i] >= 0)
      for (const auto& [j, w] : near[i])
        if (level[j] == level[i]) sets.unite(i, j);
  std::vector<std::uint32_t> lowest(m, kNone);  // per set representative: its lowest point
  for (std::uint32_t i = 0; i < m; ++i) {
    if (level[i] < 0) continue;
    auto& low = lowest[sets.find(i)];
    if (low == kNone || dist[i] < dist[low] || (dist[i] == dist[low] && i < low)) low = i;
  }
  // Components in the order of their lowest point's path length: parents come before children.
  std::vector<std::uint32_t> comps;
  for (std::uint32_t i = 0; i < m; ++i)
    if (level[i] >= 0 && sets.find(i) == i) comps.push_back(i);
  std::sort(comps.begin(), comps.end(), [&](auto a, auto b) {
    const auto la = lowest[a], lb = lowest[b];
    return dist[la] < dist[lb] || (dist[la] == dist[lb] && la < lb);
  });
  std::vector<std::uint32_t> comp_index(m, kNone);
  for (std::uint32_t k = 0; k < comps.size(); ++k) comp_index[comps[k]] = k;
  std::vector<std::uint32_t> parent(comps.size(), kNone), graft(comps.size());
  std::vector<std::size_t> graft_points(comps.size(), 0);
  std::vector<std::vector<std::uint32_t>> members(comps.size());
  for (std::uint32_t i = 0; i < m; ++i)
    if (level[i] >= 0) members[comp_index[sets.find(i)]].push_back(lost[i]);
  for (std::uint32_t k = 0; k < comps.size(); ++k) {
    const auto low = lowest[comps[k]];
    if (pred[low] == kNone) {
      graft[k] = k;
    } else {
      parent[k] = comp_index[sets.find(pred[low])];
      TREESKEL_REQUIRE(parent[k] < k, "a grafted component hangs from a later one");
      graft[k] = graft[parent[k]];
    }
    graft_points[graft[k]] += members[k].size();
  }

  // A graft that reaches no farther than `min_reach` outside the tubes is a tuft on the bark; one that
  // forks into more components per band than `max_branching` is a bush. Neither is a branch.
  std::vector<std::int64_t> lowest_level(comps.size(), std::numeric_limits<std::int64_t>::max()), highest_level(comps.size(), -1);
  std::vector<std::size_t> graft_comps(comps.size(), 0);
  std::vector<double> graft_reach(comps.size(), 0.0);
  for (std::uint32_t k = 0; k < comps.size(); ++k) {
    const auto g = graft[k];
    const auto l = level[comps[k]];
    lowest_level[g] = std::min(lowest_level[g], l);
    highest_level[g] = std::max(highest_level[g], l);
    ++graft_comps[g];
    for (auto p : members[k]) graft_reach[g] = std::max(graft_reach[g], outside[p]);
  }
  auto bushy = [&](std::uint32_t g) {
    const auto bands = static_cast<double>(highest_level[g] - lowest_level[g] + 1);
    return options.max_branching > 0.0 && static_cast<double>(graft_comps[g]) > options.max_branching * bands;
  };

  // 5. The grafts with enough points become nodes; their points leave the nodes that held them.
  std::vector<std::int64_t> node_of(comps.size(), -1);
  std::vector<char> moved(n, 0);
  std::vector<std::uint32_t> kept;
  auto candidate = [&](std::uint32_t k) {
    if (graft_points[graft[k]] < options.min_points) return false;
    return options.tufts_and_bushes || graft_reach[graft[k]] > min_reach;  // else a tuft on the bark
  };
  // With `tufts_and_bushes`, the bushes grow too, unless they hold more than `max_bush_share` of the
  // cloud: a leafy or needled crown.
  bool grow_bushes = false;
  if (options.tufts_and_bushes) {
    std::size_t in_bushes = 0;
    for (std::uint32_t k = 0; k < comps.size(); ++k)
      if (candidate(k) && bushy(graft[k])) in_bushes += members[k].size();
    grow_bushes = static_cast<double>(in_bushes) <= options.max_bush_share * static_cast<double>(cloud.size());
    stats.leafy_bushes = !grow_bushes;
  }
  for (std::uint32_t k = 0; k < comps.size(); ++k) {
    if (!candidate(k)) continue;
    if (!grow_bushes && bushy(graft[k])) {
      if (graft[k] == k) ++stats.bushy_grafts;
      stats.bushy_points += members[k].size();
      continue;
    }
    kept.push_back(k);
  }
  std::vector<SkeletonNode> made(kept.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, kept.size(), 16), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      auto& node = made[i];
      node.points = members[kept[i]];
      std::sort(node.points.begin(), node.points.end());
      node.position = l1_median(cloud.positions, node.points.data(), node.points.data() + node.points.size());
      node.radius = mean_distance(cloud.positions, node.points, node.position);
    }
  });
  for (std::size_t i = 0; i < kept.size(); ++i) {
    const auto k = kept[i];
    node_of[k] = static_cast<std::int64_t>(add_node(skeleton, made[i]));
    for (auto p : made[i].points) moved[p] = 1;
    // A graft's first node hangs from the skeleton node nearest to it, not from the node of the point
    // its path starts at: that node can lie a band away, and the long edge to it crossed other limbs
    // (on AdTree's tree33 the mesh then needed ten times the unions, 11 s instead of 1.1 s).
    const NodeId below = parent[k] == kNone ? index.nearest_node(skeleton, made[i].position) : static_cast<NodeId>(node_of[parent[k]]);
    boost::add_edge(static_cast<NodeId>(node_of[k]), below, skeleton.graph);
    if (parent[k] == kNone) ++stats.branches;
    stats.grafted_points += made[i].points.size();
  }
  stats.nodes = kept.size();
  for (NodeId v = 0; v < nodes_before; ++v) {
    auto& points = skeleton[v].points;
    points.erase(std::remove_if(points.begin(), points.end(), [&](auto p) { return moved[p] != 0; }), points.end());
  }
  return stats;
}

}  // namespace treeskel
