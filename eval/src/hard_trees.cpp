#include "treeskel/eval/hard_trees.h"

#include "treeskel/error.h"
#include "treeskel/geometry.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

namespace treeskel::eval {

namespace {

std::uint64_t mix(std::uint64_t seed, std::uint64_t salt) { return seed * 0x9E3779B97F4A7C15ULL + salt * 1000003ULL; }

Eigen::AlignedBox3d wood_box(const GroundTruth& truth) {
  Eigen::AlignedBox3d box;
  for (const auto& c : truth.cylinders) box.extend(c.a), box.extend(c.b);
  return box;
}

}  // namespace

TreeShape crowded_shape(int index) {
  if (index < 4 || index > 6) throw OptionError("crowded trees take the counts of trees 4 to 6, got " + std::to_string(index));
  const PaperTreeSpec& spec = paper_tree_specs()[index - 1];
  TreeShape shape;
  shape.branch_points = spec.branch_points;
  shape.endpoints = spec.endpoints;
  shape.leader_angle = {3.0, 12.0};
  shape.side_angle = {15.0, 35.0};
  shape.leader_length = {0.75, 0.88};
  shape.side_length = {0.55, 0.72};
  shape.lift = 0.3;
  shape.attempts = 10;
  shape.clearance = 0.15;
  return shape;
}

GroundTruth make_crowded_tree(int index, std::uint64_t seed) { return grow_truth(crowded_shape(index), mix(seed, 40 + index)); }

std::vector<HardCloud> make_crowded_clouds(std::uint64_t seed) {
  std::vector<HardCloud> clouds;
  for (int t = 4; t <= 6; ++t) {
    const GroundTruth truth = make_crowded_tree(t, seed);
    const auto& counts = paper_tree_specs()[t - 1].counts;
    for (int v = 0; v < 3; ++v) {
      SurfaceSampling s;
      s.points = counts[v];
      s.seed = mix(seed, 400 + 10 * t + v);
      clouds.push_back({"crowded" + std::to_string(t) + "_" + std::to_string(counts[v]), "crowded crowns", truth,
                        sample_cylinders(truth.cylinders, s)});
    }
  }
  return clouds;
}

PointCloud virtual_scan(const GroundTruth& truth, const ScanOptions& options) {
  if (options.scanners < 1) throw OptionError("virtual_scan: at least one scanner");
  const Eigen::AlignedBox3d box = wood_box(truth);
  const double size = box.sizes().maxCoeff();
  const Eigen::Vector3d base = truth.skeleton[truth.skeleton.root].position;
  std::mt19937_64 rng(mix(options.seed, 7));
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double azimuth0 = 2 * M_PI * unit(rng);
  PointCloud cloud;
  for (int k = 0; k < options.scanners; ++k) {
    const double azimuth = azimuth0 + 2 * M_PI * k / options.scanners + 0.4 * (unit(rng) - 0.5);
    SurfaceSampling s;
    s.points = options.points / options.scanners + (k < static_cast<int>(options.points % options.scanners) ? 1 : 0);
    s.seed = mix(options.seed, 100 + k);
    s.noise = options.noise;
    s.viewpoint = base + size * Eigen::Vector3d(options.distance * std::cos(azimuth), options.distance * std::sin(azimuth),
                                                options.height);
    const PointCloud seen = sample_cylinders(truth.cylinders, s);
    cloud.positions.insert(cloud.positions.end(), seen.positions.begin(), seen.positions.end());
  }
  return cloud;
}

GroundTruth cut_to_scan(const GroundTruth& truth, const PointCloud& cloud, const CutOptions& options) {
  const Skeleton& s = truth.skeleton;
  const std::size_t n = s.node_count();
  const std::vector<NodeId> parent = parents_from_root(s.graph, s.root);
  std::vector<int> children(n, 0);
  for (NodeId v = 0; v < n; ++v)
    if (v != s.root) ++children[parent[v]];
  std::vector<char> forks(n, 0);  // in the truth as it was given
  for (NodeId v = 0; v < n; ++v) forks[v] = children[v] > 1;
  const Eigen::Vector3d shift = s.offset - cloud.offset;  // a node's position in the cloud's frame
  // With own_points: the points of each edge (named by its child node), each point given to the
  // edge whose tube surface lies nearest.
  std::vector<std::vector<std::uint32_t>> owned(n);
  if (options.own_points && n > 1) {
    // Each edge's midpoint and the farthest its surface reaches from it: a lower bound of a point's
    // distance to the surface skips most edges.
    std::vector<Eigen::Vector3d> mid(n);
    std::vector<double> extent(n, 0.0);
    for (NodeId c = 0; c < n; ++c) {
      if (c == s.root) continue;
      mid[c] = 0.5 * (s[parent[c]].position + s[c].position) + shift;
      extent[c] = 0.5 * (s[c].position - s[parent[c]].position).norm() + std::max(s[c].radius, s[parent[c]].radius);
    }
    NodeId last = s.root;
    for (std::uint32_t i = 0; i < cloud.size(); ++i) {
      const Eigen::Vector3d& p = cloud.positions[i];
      // How far `p` lies outside the tube of edge `c` (its nodes moved to the cloud's frame).
      const auto outside = [&](NodeId c) {
        return outside_tube(p, s[parent[c]].position + shift, s[c].position + shift, s[parent[c]].radius, s[c].radius);
      };
      double best = std::numeric_limits<double>::infinity();
      NodeId owner = s.root;
      if (last != s.root) best = outside(last), owner = last;  // the previous point's edge first
      for (NodeId c = 0; c < n; ++c) {
        if (c == s.root || c == last || (p - mid[c]).norm() - extent[c] >= best) continue;
        if (const double d = outside(c); d < best) best = d, owner = c;
      }
      last = owner;
      if (owner != s.root) owned[owner].push_back(i);
    }
  }
  const auto seen = [&](NodeId v) {
    const double reach = s[v].radius + options.reach, reach2 = reach * reach;
    const Eigen::Vector3d at = s[v].position + shift;
    int found = 0;
    if (!options.own_points) {
      for (const auto& p : cloud.positions)
        if ((p - at).squaredNorm() <= reach2 && ++found >= options.min_points) return true;
      return false;
    }
    // The edges from `v` down its own branch, up to the fork it leaves, while they start within reach
    // of it (past the fork, the points are the parent branch's).
    for (NodeId u = v; u != s.root; u = parent[u]) {
      for (auto i : owned[u])
        if ((cloud.positions[i] - at).squaredNorm() <= reach2 && ++found >= options.min_points) return true;
      const NodeId below = parent[u];
      if (below == s.root || forks[below] || (s[below].position - s[v].position).norm() > reach) break;
    }
    return false;
  };
  std::vector<char> removed(n, 0);
  std::vector<NodeId> tips;
  for (NodeId v = 0; v < n; ++v)
    if (v != s.root && children[v] == 0) tips.push_back(v);
  while (!tips.empty()) {
    const NodeId v = tips.back();
    tips.pop_back();
    if (seen(v)) continue;
    removed[v] = 1;
    const NodeId p = parent[v];
    if (--children[p] == 0 && p != s.root) tips.push_back(p);
  }
  GroundTruth cut;
  cut.cylinders = truth.cylinders;
  std::vector<NodeId> renumbered(n);
  for (NodeId v = 0; v < n; ++v)
    if (!removed[v]) renumbered[v] = add_node(cut.skeleton, s[v]);
  for (NodeId v = 0; v < n; ++v)
    if (!removed[v] && v != s.root) boost::add_edge(renumbered[parent[v]], renumbered[v], cut.skeleton.graph);
  cut.skeleton.root = renumbered[s.root];
  cut.skeleton.offset = s.offset;
  return cut;
}

std::vector<HardCloud> make_sparse_clouds(std::uint64_t seed, const CutOptions& cut) {
  std::vector<HardCloud> clouds;
  const int sizes[] = {60, 130, 230};
  for (int b : sizes) {
    TreeShape shape;
    shape.branch_points = b;
    shape.endpoints = b + 2 + b / 3;
    const GroundTruth truth = grow_truth(shape, mix(seed, 500 + b));
    std::mt19937_64 rng(mix(seed, 600 + b));
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int density = 0; density < 2; ++density)
      for (int scanners = 1; scanners <= 3; ++scanners) {
        ScanOptions scan;
        scan.scanners = scanners;
        scan.points = density == 0 ? 2000 + static_cast<std::size_t>(1000 * unit(rng))
                                   : 4000 + static_cast<std::size_t>(2200 * unit(rng));
        scan.seed = mix(seed, 700 + 10 * b + 3 * density + scanners);
        PointCloud cloud = virtual_scan(truth, scan);
        clouds.push_back({"sparse" + std::to_string(b) + "_" + std::to_string(scanners) + "view" +
                              (scanners > 1 ? "s" : "") + "_" + std::to_string(cloud.size()),
                          density == 0 ? "sparse scans, 2,000-3,000 points" : "sparse scans, 4,000-6,200 points",
                          cut_to_scan(truth, cloud, cut), std::move(cloud)});
      }
  }
  return clouds;
}

std::vector<HardCloud> make_combined_clouds(std::uint64_t seed) {
  std::vector<HardCloud> clouds;
  for (int t = 1; t <= 6; ++t) {
    const GroundTruth truth = make_paper_tree(t, seed);
    const std::size_t target = paper_tree_specs()[t - 1].counts[0];
    std::mt19937_64 rng(mix(seed, 800 + t));
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const Eigen::AlignedBox3d box = wood_box(truth);
    // One side, with noise, five times denser than needed: holes and density waves thin it out.
    const double azimuth = 2 * M_PI * unit(rng);
    SurfaceSampling s;
    s.points = 5 * target;
    s.seed = mix(seed, 900 + t);
    s.noise = 0.003;
    s.facing = Eigen::Vector3d(std::cos(azimuth), std::sin(azimuth), 0.15).normalized();
    const PointCloud seen = sample_cylinders(truth.cylinders, s);
    std::vector<std::pair<Eigen::Vector3d, double>> holes;
    for (int h = 0; h < 4; ++h)
      holes.emplace_back(seen.positions[static_cast<std::size_t>(unit(rng) * seen.size()) % seen.size()],
                         0.02 + 0.03 * unit(rng));
    const Eigen::Vector3d axis = Eigen::Vector3d(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5).normalized();
    const double phase = 2 * M_PI * unit(rng);
    PointCloud kept;
    for (const auto& p : seen.positions) {
      if (kept.size() == target) break;
      if (std::any_of(holes.begin(), holes.end(), [&](const auto& h) { return (p - h.first).norm() < h.second; })) continue;
      const double keep = 0.08 + 0.92 * (0.5 + 0.5 * std::sin(2 * M_PI * 2.0 * p.dot(axis) + phase));
      if (unit(rng) < keep) kept.positions.push_back(p);
    }
    for (std::size_t o = 0; o < kept.size() / 100; ++o)
      kept.positions[static_cast<std::size_t>(unit(rng) * kept.size()) % kept.size()] =
          box.min() + (box.max() - box.min()).cwiseProduct(Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
    clouds.push_back({"tree" + std::to_string(t) + "_all", "every degradation at once", truth, std::move(kept)});
  }
  return clouds;
}

std::vector<HardCloud> make_hard_clouds(std::uint64_t seed, const CutOptions& cut) {
  std::vector<HardCloud> clouds = make_crowded_clouds(seed);
  for (auto& c : make_sparse_clouds(seed, cut)) clouds.push_back(std::move(c));
  for (auto& c : make_combined_clouds(seed)) clouds.push_back(std::move(c));
  return clouds;
}

}  // namespace treeskel::eval
