#include "treeskel/forest/wood.h"

#include "treeskel/disjoint_sets.h"
#include "treeskel/error.h"
#include "treeskel/kd_search.h"

#include <Eigen/Eigenvalues>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <queue>

namespace treeskel::forest {

namespace {

constexpr std::size_t kNear = 40;    // neighbours of the shape and the density
constexpr std::size_t kSmooth = 20;  // ... the score is averaged over

/// The shape part of the score, 0.25 planarity - scattering, from the sums of `count` points
/// (positions relative to one of them, so that the sums stay small).
double shape_term(const Eigen::Vector3d& sum, const Eigen::Matrix3d& outer, std::size_t count) {
  const double n = static_cast<double>(count);
  const Eigen::Vector3d mean = sum / n;
  const Eigen::Matrix3d cov = outer / n - mean * mean.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(cov, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d l = eig.eigenvalues().cwiseMax(0.0);  // ascending
  if (!(l(2) > 0)) return 0.0;
  return 0.25 * (l(1) - l(0)) / l(2) - l(0) / l(2);
}

/// The median of the distances to the 40th neighbour (the largest when that is 0: duplicates).
double median_reach(std::vector<double> reach) {
  const std::size_t half = reach.size() / 2;
  std::nth_element(reach.begin(), reach.begin() + static_cast<std::ptrdiff_t>(half), reach.end());
  const double median = reach[half];
  return median > 0 ? median : std::max(*std::max_element(reach.begin(), reach.end()), 1e-300);
}

/// The density part of the score: -0.25 ln(d40 / median d40). A distance of 0 (duplicate points) is
/// not infinitely dense: it counts as a thousandth of the median.
double density_term(double reach, double median) { return -0.25 * std::log(std::max(reach, median * 1e-3) / median); }

/// The neighbour graph, both ways, as compressed rows: point p's neighbours are
/// adjacent[start[p] .. start[p + 1]).
struct Graph {
  std::vector<std::uint32_t> start, adjacent;
};

/// The graph of each point's kSmooth nearest (`nearest`, itself first), both ways.
Graph neighbour_graph(std::size_t n, const std::vector<std::uint32_t>& nearest) {
  Graph g;
  g.start.assign(n + 1, 0);
  for (std::size_t p = 0; p < n; ++p)
    for (std::size_t k = 1; k < kSmooth; ++k) {
      ++g.start[p + 1];
      ++g.start[nearest[p * kSmooth + k] + 1];
    }
  for (std::size_t p = 0; p < n; ++p) g.start[p + 1] += g.start[p];
  std::vector<std::uint32_t> next(g.start.begin(), g.start.end() - 1);
  g.adjacent.resize(g.start[n]);
  for (std::size_t p = 0; p < n; ++p)
    for (std::size_t k = 1; k < kSmooth; ++k) {
      const std::uint32_t q = nearest[p * kSmooth + k];
      g.adjacent[next[p]++] = q;
      g.adjacent[next[q]++] = static_cast<std::uint32_t>(p);
    }
  return g;
}

/// Per point, how many points' shortest way down the neighbour graph to the tree's base passes
/// through it (itself included): the shortest-path tree from the lowest point along `up`, by
/// Euclidean length, each point's count the size of its subtree. A part of the graph the base does
/// not reach gets a tree of its own from its own lowest point. Wood carries the ways to everything
/// beyond it; a cluster of leaves, at the end of the ways, carries little.
std::vector<double> ways_through(const PointCloud& cloud, const Graph& graph, const Eigen::Vector3d& up) {
  const std::size_t n = cloud.size();
  std::vector<double> height(n);
  for (std::size_t p = 0; p < n; ++p) height[p] = cloud.positions[p].dot(up);
  std::vector<std::uint32_t> by_height(n);
  for (std::size_t p = 0; p < n; ++p) by_height[p] = static_cast<std::uint32_t>(p);
  std::stable_sort(by_height.begin(), by_height.end(), [&](std::uint32_t a, std::uint32_t b) { return height[a] < height[b]; });
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  std::vector<double> cost(n, std::numeric_limits<double>::infinity());
  std::vector<std::uint32_t> from(n, kNone), settled;
  std::vector<std::uint8_t> done(n, 0);
  settled.reserve(n);
  using Item = std::pair<double, std::uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  for (const std::uint32_t base : by_height) {
    if (done[base]) continue;
    cost[base] = 0;
    queue.emplace(0.0, base);
    while (!queue.empty()) {
      const auto [c, p] = queue.top();
      queue.pop();
      if (done[p]) continue;
      done[p] = 1;
      settled.push_back(p);
      for (std::uint32_t e = graph.start[p]; e < graph.start[p + 1]; ++e) {
        const std::uint32_t q = graph.adjacent[e];
        const double d = c + (cloud.positions[q] - cloud.positions[p]).norm();
        if (!done[q] && d < cost[q]) {
          cost[q] = d;
          from[q] = p;
          queue.emplace(d, q);
        }
      }
    }
  }
  std::vector<double> count(n, 1.0);
  for (std::size_t i = settled.size(); i-- > 0;)
    if (from[settled[i]] != kNone) count[from[settled[i]]] += count[settled[i]];
  return count;
}

/// The wood cut off from the largest part of it by points called leaves (a twig in a crown whose bark
/// looks like foliage for a stretch) joined back: the points called leaves on the shortest way back
/// from each part of `min_part` points or more, the way measured along the neighbour graph
/// (`graph`) by the length it runs through such points.
/// Returns how many points it turned to wood.
std::size_t join_wood(const PointCloud& cloud, const Graph& graph, std::vector<std::uint8_t>& wood,
                      std::size_t min_part) {
  const std::size_t n = cloud.size();
  const std::vector<std::uint32_t>& start = graph.start;
  const std::vector<std::uint32_t>& adjacent = graph.adjacent;
  // The parts of the wood; the largest (the lowest representative of equals) is the stem's.
  DisjointSets<std::uint32_t> parts(n);
  for (std::size_t p = 0; p < n; ++p)
    if (wood[p])
      for (std::uint32_t e = start[p]; e < start[p + 1]; ++e)
        if (wood[adjacent[e]]) parts.unite(static_cast<std::uint32_t>(p), adjacent[e]);
  std::vector<std::uint32_t> size(n, 0);
  for (std::size_t p = 0; p < n; ++p) size[parts.find(static_cast<std::uint32_t>(p))] += wood[p];
  const auto main = static_cast<std::uint32_t>(std::max_element(size.begin(), size.end()) - size.begin());
  if (size[main] == 0) return 0;
  // Shortest ways from the largest part: steps onto wood cost nothing, onto leaves their length.
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  std::vector<double> cost(n, std::numeric_limits<double>::infinity());
  std::vector<std::uint32_t> from(n, kNone);
  using Item = std::pair<double, std::uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  for (std::size_t p = 0; p < n; ++p)
    if (wood[p] && parts.find(static_cast<std::uint32_t>(p)) == main) {
      cost[p] = 0;
      queue.emplace(0.0, static_cast<std::uint32_t>(p));
    }
  while (!queue.empty()) {
    const auto [c, p] = queue.top();
    queue.pop();
    if (c > cost[p]) continue;
    for (std::uint32_t e = start[p]; e < start[p + 1]; ++e) {
      const std::uint32_t q = adjacent[e];
      const double d = c + (wood[q] ? 0.0 : (cloud.positions[q] - cloud.positions[p]).norm());
      if (d < cost[q]) {
        cost[q] = d;
        from[q] = p;
        queue.emplace(d, q);
      }
    }
  }
  // From each other part of min_part points or more: its cheapest point's way back, to wood.
  std::vector<std::uint32_t> entry(n, kNone);
  for (std::size_t p = 0; p < n; ++p) {
    if (!wood[p]) continue;
    const std::uint32_t r = parts.find(static_cast<std::uint32_t>(p));
    if (r == main || size[r] < min_part || !std::isfinite(cost[p])) continue;
    if (entry[r] == kNone || cost[p] < cost[entry[r]]) entry[r] = static_cast<std::uint32_t>(p);
  }
  std::size_t joined = 0;
  for (std::size_t r = 0; r < n; ++r)
    for (std::uint32_t p = entry[r]; p != kNone && cost[p] > 0; p = from[p])
      if (!wood[p]) {
        wood[p] = 1;
        ++joined;
      }
  return joined;
}

}  // namespace

double WoodLeaf::leaf_share() const {
  const std::size_t n = wood_points + leaf_points;
  return n ? static_cast<double>(leaf_points) / static_cast<double>(n) : 0.0;
}

WoodLeaf separate_wood(const PointCloud& cloud, const WoodOptions& options) {
  const std::size_t n = cloud.size();
  WoodLeaf out;
  out.is_wood.assign(n, 1);
  out.score.assign(n, 0.0f);
  out.wood_points = n;
  if (n <= kNear) return out;

  std::vector<kd::Point> points(n);
  for (std::size_t p = 0; p < n; ++p) points[p] = kd::Point(cloud.positions[p].x(), cloud.positions[p].y(), cloud.positions[p].z());
  std::vector<std::uint32_t> ids(n);
  for (std::size_t p = 0; p < n; ++p) ids[p] = static_cast<std::uint32_t>(p);
  kd::Tree tree(ids.begin(), ids.end(), kd::Tree::Splitter(), kd::Traits(kd::PointMap(points.data())));
  tree.build();

  // Per point: the shape terms of the score, the distance to its 40th neighbour, its 20 nearest.
  std::vector<double> partial(n), reach(n);
  std::vector<std::uint32_t> nearest(n * kSmooth);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t p = range.begin(); p != range.end(); ++p) {
      kd::KnnSearch search(tree, points[p], kNear, 0, true, kd::KnnSearch::Distance(kd::PointMap(points.data())));
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
      std::size_t k = 0;
      for (auto it = search.begin(); it != search.end(); ++it, ++k) {
        // Relative to the point itself, so that the sums stay small.
        const Eigen::Vector3d q = cloud.positions[it->first] - cloud.positions[p];
        sum += q;
        outer += q * q.transpose();
        if (k < kSmooth) nearest[p * kSmooth + k] = it->first;
        reach[p] = std::sqrt(it->second);
      }
      partial[p] = shape_term(sum, outer, k);
    }
  });
  // Density relative to the cloud's own: the median distance to the 40th neighbour.
  const double median = median_reach(reach);
  std::vector<double> raw(n);
  for (std::size_t p = 0; p < n; ++p) raw[p] = partial[p] + density_term(reach[p], median);
  // The shape and density, averaged over the 20 nearest.
  std::size_t leaves = 0;
  for (std::size_t p = 0; p < n; ++p) {
    double s = 0;
    for (std::size_t k = 0; k < kSmooth; ++k) s += raw[nearest[p * kSmooth + k]];
    s /= static_cast<double>(kSmooth);
    out.score[p] = static_cast<float>(s);
    leaves += !(s > options.threshold);
  }
  // The neighbour graph, built once if the ways or the joining need it.
  std::optional<Graph> graph;
  const auto neighbours = [&]() -> const Graph& {
    if (!graph) graph = neighbour_graph(n, nearest);
    return *graph;
  };
  // A cloud in leaf (by the share the shape and density call leaves) also weighs the ways through
  // each point: its leaves hang at the ends of the ways, and its twigs carry them.
  const double share = static_cast<double>(leaves) / static_cast<double>(n);
  const double span = options.ways_full_share - options.ways_from_share;
  if (options.ways_weight != 0)
    out.in_leaf = span > 0 ? std::clamp((share - options.ways_from_share) / span, 0.0, 1.0) : static_cast<double>(share >= options.ways_full_share);
  if (out.in_leaf > 0) {
    const std::vector<double> ways = ways_through(cloud, neighbours(), options.up.normalized());
    const double weight = out.in_leaf * options.ways_weight;
    for (std::size_t p = 0; p < n; ++p) {
      double most = 1;
      for (std::size_t k = 0; k < kSmooth; ++k) most = std::max(most, ways[nearest[p * kSmooth + k]]);
      out.score[p] += static_cast<float>(weight * std::log2(most / options.ways_reference));
    }
  }
  for (std::size_t p = 0; p < n; ++p) out.is_wood[p] = out.score[p] > options.threshold;
  if (options.join_parts > 0 && std::count(out.is_wood.begin(), out.is_wood.end(), 1) > 0)
    out.joined = join_wood(cloud, neighbours(), out.is_wood, options.join_parts);
  out.wood_points = static_cast<std::size_t>(std::count(out.is_wood.begin(), out.is_wood.end(), 1));
  out.leaf_points = n - out.wood_points;
  return out;
}

double estimate_leaf_share(const PointCloud& cloud, const LeafShareSample& sample) {
  const std::size_t n = cloud.size(), sites = std::max<std::size_t>(sample.sites, 1);
  const std::size_t crop = std::max(sample.crop, kNear + 1), inner = std::min(std::max<std::size_t>(sample.inner, 1), crop);
  WoodOptions shape_only;
  shape_only.ways_weight = 0;
  shape_only.join_parts = 0;
  if (n <= std::max(sample.whole_up_to, kNear * sites)) return separate_wood(cloud, shape_only).leaf_share();
  // The points in a grid of about 8 a cell over the bounding cube, sorted by cell (a counting sort:
  // one pass), so that each site's crop is found by rings of cells around it.
  Eigen::AlignedBox3d box;
  for (const auto& p : cloud.positions) box.extend(p);
  const double side = std::max(box.sizes().maxCoeff(), 1e-300);
  const auto cells_per_axis = static_cast<long>(std::clamp(std::cbrt(static_cast<double>(n) / 8.0), 1.0, 256.0));  // at most 16.8 M cells
  const double cell = side / static_cast<double>(cells_per_axis);
  std::array<long, 3> dims{};
  for (int a = 0; a < 3; ++a) dims[a] = std::clamp(static_cast<long>(box.sizes()[a] / cell) + 1, 1L, cells_per_axis);
  const auto cell_of = [&](const Eigen::Vector3d& p) {
    std::array<long, 3> c{};
    for (int a = 0; a < 3; ++a) c[a] = std::clamp(static_cast<long>((p[a] - box.min()[a]) / cell), 0L, dims[a] - 1);
    return c;
  };
  const auto index_of = [&](const std::array<long, 3>& c) { return static_cast<std::size_t>((c[2] * dims[1] + c[1]) * dims[0] + c[0]); };
  std::vector<std::size_t> start(static_cast<std::size_t>(dims[0] * dims[1] * dims[2]) + 1, 0);
  std::vector<std::uint32_t> cell_index(n);
  for (std::size_t p = 0; p < n; ++p) ++start[(cell_index[p] = static_cast<std::uint32_t>(index_of(cell_of(cloud.positions[p])))) + 1];
  for (std::size_t c = 0; c + 1 < start.size(); ++c) start[c + 1] += start[c];
  std::vector<std::uint32_t> order(n);
  {
    std::vector<std::size_t> next(start.begin(), start.end() - 1);
    for (std::size_t p = 0; p < n; ++p) order[next[cell_index[p]]++] = static_cast<std::uint32_t>(p);
  }
  // Within each crop, by brute force: each counted point's kSmooth nearest, and the score's terms
  // for those. The crops are scored apart and in parallel; the median over all of them.
  struct Crop {
    std::vector<std::uint32_t> smooth;  // per counted point, its kSmooth nearest (crop indices)
    std::vector<double> shape, reach;   // per crop point (NaN: not needed)
  };
  std::vector<Crop> crops(sites);
  tbb::parallel_for(std::size_t(0), sites, [&](std::size_t s) {
    // The site: a point evenly through the cloud's order. Its crop: the `crop` nearest points, found
    // ring by ring of cells until no cell farther out can hold a nearer one.
    const Eigen::Vector3d& site = cloud.positions[(2 * s + 1) * n / (2 * sites)];
    const std::array<long, 3> centre = cell_of(site);
    std::vector<std::pair<double, std::uint32_t>> found;  // (squared distance, point)
    for (long ring = 0;; ++ring) {
      for (long z = centre[2] - ring; z <= centre[2] + ring; ++z)
        for (long y = centre[1] - ring; y <= centre[1] + ring; ++y)
          for (long x = centre[0] - ring; x <= centre[0] + ring; ++x) {
            if (std::max({std::abs(x - centre[0]), std::abs(y - centre[1]), std::abs(z - centre[2])}) != ring) continue;
            if (x < 0 || y < 0 || z < 0 || x >= dims[0] || y >= dims[1] || z >= dims[2]) continue;
            const std::size_t c = index_of({x, y, z});
            for (std::size_t i = start[c]; i < start[c + 1]; ++i)
              found.emplace_back((cloud.positions[order[i]] - site).squaredNorm(), order[i]);
          }
      // Any point of ring + 1 or beyond lies at least `ring` cells away.
      const double beyond = static_cast<double>(ring) * cell;
      const bool whole_grid = ring >= std::max({dims[0], dims[1], dims[2]});
      if (found.size() >= crop || whole_grid) {
        const std::size_t k = std::min(crop, found.size());
        std::nth_element(found.begin(), found.begin() + static_cast<std::ptrdiff_t>(k - 1), found.end());
        if (whole_grid || found[k - 1].first <= beyond * beyond) {
          found.resize(k);
          break;
        }
      }
    }
    std::sort(found.begin(), found.end());
    if (found.size() <= kNear) return;
    std::vector<std::uint32_t> points;
    for (const auto& f : found) points.push_back(f.second);
    const std::size_t m = points.size(), counted = std::min(inner, m);
    // The `k` nearest of crop point i (itself first), by distance then index.
    std::vector<std::pair<double, std::uint32_t>> by(m);
    const auto nearest = [&](std::size_t i, std::size_t k) {
      for (std::size_t j = 0; j < m; ++j) by[j] = {(cloud.positions[points[j]] - cloud.positions[points[i]]).squaredNorm(), static_cast<std::uint32_t>(j)};
      const auto kth = by.begin() + static_cast<std::ptrdiff_t>(k);
      std::nth_element(by.begin(), kth - 1, by.end());
      std::sort(by.begin(), kth);
    };
    Crop& c = crops[s];
    c.shape.assign(m, std::numeric_limits<double>::quiet_NaN());
    c.reach.assign(m, std::numeric_limits<double>::quiet_NaN());
    for (std::size_t i = 0; i < counted; ++i) {
      nearest(i, kSmooth);
      for (std::size_t k = 0; k < kSmooth; ++k) c.smooth.push_back(by[k].second);
    }
    for (const std::uint32_t i : c.smooth) {
      if (!std::isnan(c.shape[i])) continue;
      nearest(i, kNear);
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
      for (std::size_t k = 0; k < kNear; ++k) {
        const Eigen::Vector3d q = cloud.positions[points[by[k].second]] - cloud.positions[points[i]];
        sum += q;
        outer += q * q.transpose();
      }
      c.shape[i] = shape_term(sum, outer, kNear);
      c.reach[i] = std::sqrt(by[kNear - 1].first);
    }
  });
  std::vector<double> reach;
  for (const Crop& c : crops)
    for (const double r : c.reach)
      if (!std::isnan(r)) reach.push_back(r);
  if (reach.empty()) return separate_wood(cloud, shape_only).leaf_share();
  const double median = median_reach(std::move(reach));
  const WoodOptions defaults;
  std::size_t leaves = 0, total = 0;
  for (const Crop& c : crops)
    for (std::size_t i = 0; i < c.smooth.size(); i += kSmooth) {
      double score = 0;
      for (std::size_t k = 0; k < kSmooth; ++k) score += c.shape[c.smooth[i + k]] + density_term(c.reach[c.smooth[i + k]], median);
      ++total;
      leaves += score / static_cast<double>(kSmooth) <= defaults.threshold;
    }
  return static_cast<double>(leaves) / static_cast<double>(total);
}

PointCloud select_points(const PointCloud& cloud, const std::vector<std::uint8_t>& keep, std::uint8_t value) {
  TREESKEL_REQUIRE(keep.size() == cloud.size(), "a flag per point");
  PointCloud out;
  out.offset = cloud.offset;
  for (std::size_t p = 0; p < cloud.size(); ++p) {
    if (keep[p] != value) continue;
    append_point(out, cloud, p);
  }
  return out;
}

}  // namespace treeskel::forest
