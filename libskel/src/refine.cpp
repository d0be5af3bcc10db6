#include "treeskel/refine.h"

#include "treeskel/l1_median.h"
#include "treeskel/level_sets.h"

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace treeskel {

namespace {

/// Lloyd's k-means of `points` from the given seeds. Returns the cluster of every point.
std::vector<int> kmeans(const std::vector<Eigen::Vector3d>& positions, const std::vector<std::uint32_t>& points,
                        std::vector<Eigen::Vector3d> centres, int iterations) {
  const std::size_t k = centres.size();
  std::vector<int> label(points.size(), -1);
  for (int it = 0; it < iterations; ++it) {
    bool changed = false;
    for (std::size_t i = 0; i < points.size(); ++i) {
      int best = 0;
      double best_d = std::numeric_limits<double>::infinity();
      for (std::size_t j = 0; j < k; ++j) {
        const double d = (positions[points[i]] - centres[j]).squaredNorm();
        if (d < best_d) {
          best_d = d;
          best = static_cast<int>(j);
        }
      }
      if (label[i] != best) {
        label[i] = best;
        changed = true;
      }
    }
    if (!changed) break;
    std::vector<Eigen::Vector3d> sum(k, Eigen::Vector3d::Zero());
    std::vector<std::size_t> count(k, 0);
    for (std::size_t i = 0; i < points.size(); ++i) {
      sum[label[i]] += positions[points[i]];
      ++count[label[i]];
    }
    for (std::size_t j = 0; j < k; ++j)
      if (count[j] > 0) centres[j] = sum[j] / static_cast<double>(count[j]);
  }
  return label;
}

Eigen::Vector3d cpc_of(const PointCloud& cloud, const std::vector<std::uint32_t>& points, const CpcOptions& options) {
  const auto* first = points.data();
  const auto* last = first + points.size();
  return cpc_centre(cloud.positions, first, last, l1_median(cloud.positions, first, last), options);
}

/// What refining one fork does, worked out from the fork and its children as they are: which child
/// branches leave it for a node of their own, where those nodes go, and where the fork moves.
struct ForkPlan {
  std::vector<NodeId> children;             // sorted
  Eigen::Vector3d fork_at = Eigen::Vector3d::Zero();  // the fork's position and point count, and
  std::size_t fork_points = 0;                        // the children's positions and radii, it was made from
  std::vector<Eigen::Vector3d> at;
  std::vector<double> radii;
  std::vector<std::vector<std::uint32_t>> clusters;
  std::vector<bool> split;                  // child j leaves with clusters[j]
  std::vector<Eigen::Vector3d> centre;      // of each cluster that splits
  std::vector<double> radius;
  std::size_t splits = 0;
  std::vector<std::uint32_t> rest;          // the fork's points left (sorted), when some child stays
  Eigen::Vector3d rest_centre = Eigen::Vector3d::Zero();
  double rest_radius = 0.0;

  bool still_fits(const SkeletonGraph& g, NodeId q, const std::vector<NodeId>& now) const {
    if (now != children || g[q].position != fork_at || g[q].points.size() != fork_points) return false;
    for (std::size_t j = 0; j < children.size(); ++j)
      if (g[children[j]].position != at[j] || g[children[j]].radius != radii[j]) return false;
    return true;
  }
};

std::vector<NodeId> children_of(const SkeletonGraph& g, NodeId q, NodeId up) {
  std::vector<NodeId> children;
  for (auto w : boost::make_iterator_range(boost::adjacent_vertices(q, g)))
    if (w != up) children.push_back(w);
  std::sort(children.begin(), children.end());
  return children;
}

ForkPlan plan_fork(const SkeletonGraph& g, NodeId q, std::vector<NodeId> children, const PointCloud& cloud,
                   const RefineOptions& options) {
  ForkPlan plan;
  plan.children = std::move(children);
  plan.fork_at = g[q].position;
  plan.fork_points = g[q].points.size();
  const std::size_t k = plan.children.size();
  for (auto c : plan.children) {
    plan.at.push_back(g[c].position);
    plan.radii.push_back(g[c].radius);
  }
  const auto& points = g[q].points;
  if (k < 2 || points.size() < k * options.min_cluster_points) return plan;

  // Seeds: the point of q nearest to each child branch.
  std::vector<Eigen::Vector3d> seeds;
  for (auto c : plan.children) {
    const auto nearest = *std::min_element(points.begin(), points.end(), [&](auto a, auto b) {
      return (cloud.positions[a] - g[c].position).squaredNorm() < (cloud.positions[b] - g[c].position).squaredNorm();
    });
    seeds.push_back(cloud.positions[nearest]);
  }
  const auto label = kmeans(cloud.positions, points, seeds, options.kmeans_iterations);

  double sum_r2 = 0.0;
  for (auto r : plan.radii) sum_r2 += r * r;
  const double tau = options.eta * std::sqrt(sum_r2);

  plan.clusters.resize(k);
  for (std::size_t i = 0; i < points.size(); ++i) plan.clusters[label[i]].push_back(points[i]);
  plan.split.assign(k, false);
  plan.centre.assign(k, Eigen::Vector3d::Zero());
  plan.radius.assign(k, 0.0);
  for (std::size_t j = 0; j < k; ++j) {
    if (plan.clusters[j].size() < options.min_cluster_points) continue;
    const Eigen::Vector3d centre = cpc_of(cloud, plan.clusters[j], options.cpc);
    if ((centre - g[q].position).norm() <= tau) continue;
    plan.split[j] = true;
    plan.centre[j] = centre;
    plan.radius[j] = mean_distance(cloud.positions, plan.clusters[j], centre);
    ++plan.splits;
  }
  if (plan.splits == 0 || plan.splits == k) return plan;
  for (std::size_t j = 0; j < k; ++j)
    if (!plan.split[j]) plan.rest.insert(plan.rest.end(), plan.clusters[j].begin(), plan.clusters[j].end());
  std::sort(plan.rest.begin(), plan.rest.end());
  if (!plan.rest.empty()) {
    plan.rest_centre = cpc_of(cloud, plan.rest, options.cpc);
    plan.rest_radius = mean_distance(cloud.positions, plan.rest, plan.rest_centre);
  }
  return plan;
}

}  // namespace

std::size_t refine_topology(Skeleton& skeleton, const PointCloud& cloud, const RefineOptions& options) {
  auto& g = skeleton.graph;
  const std::size_t n0 = boost::num_vertices(g);
  if (n0 < 3) return 0;
  std::vector<NodeId> parent = parents_from_root(g, skeleton.root);
  std::vector<double> geodesic(n0, 0.0);
  for (auto v : bfs_order(g, skeleton.root))
    if (v != skeleton.root) geodesic[v] = geodesic[parent[v]] + (g[v].position - g[parent[v]].position).norm();

  std::vector<NodeId> order;
  for (NodeId v = 0; v < n0; ++v)
    if (v != skeleton.root && boost::degree(v, g) > 2) order.push_back(v);
  std::sort(order.begin(), order.end(), [&](NodeId a, NodeId b) {
    return geodesic[a] > geodesic[b] || (geodesic[a] == geodesic[b] && a < b);
  });

  // Forks are refined from the tips down, and a fork's refinement can change its parent's children.
  // Every fork is planned at once (in parallel) from the skeleton as it is; going down, a plan whose
  // fork's children have changed since is made again, so the result is that of one fork at a time.
  // On one thread nothing is planned ahead (a plan made again would be work lost).
  std::vector<ForkPlan> plans(order.size());
  const bool ahead = tbb::this_task_arena::max_concurrency() > 1 &&
                     tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism) > 1;
  if (ahead)
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), 4), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i)
        plans[i] = plan_fork(g, order[i], children_of(g, order[i], parent[order[i]]), cloud, options);
    });

  std::vector<bool> keep(n0, true);
  std::size_t added = 0;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const NodeId q = order[i];
    const NodeId up = parent[q];
    auto now = children_of(g, q, up);
    if (!ahead || !plans[i].still_fits(g, q, now)) plans[i] = plan_fork(g, q, std::move(now), cloud, options);
    ForkPlan& plan = plans[i];
    if (plan.splits == 0) continue;
    const std::size_t k = plan.children.size();
    for (std::size_t j = 0; j < k; ++j) {
      if (!plan.split[j]) continue;
      SkeletonNode sibling;
      sibling.position = plan.centre[j];
      sibling.points = std::move(plan.clusters[j]);
      sibling.radius = plan.radius[j];
      const NodeId s = add_node(skeleton, sibling);
      keep.push_back(true);
      parent.push_back(up);
      boost::add_edge(s, up, g);
      boost::remove_edge(plan.children[j], q, g);
      boost::add_edge(plan.children[j], s, g);
      parent[plan.children[j]] = s;
    }
    added += plan.splits;
    g[q].points = std::move(plan.rest);
    if (plan.splits == k) {
      // Every branch left q, with all its points: q would be an empty tip, and goes.
      keep[q] = false;
      boost::clear_vertex(q, g);
    } else if (!g[q].points.empty()) {
      g[q].position = plan.rest_centre;
      g[q].radius = plan.rest_radius;
    }
    plan = ForkPlan();
  }
  if (std::find(keep.begin(), keep.end(), false) != keep.end()) compact_nodes(skeleton, keep);
  return added;
}

}  // namespace treeskel
