#include "treeskel/refine.h"

#include "treeskel/l1_median.h"
#include "treeskel/level_sets.h"

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

  std::vector<bool> keep(n0, true);
  std::size_t added = 0;
  for (const NodeId q : order) {
    const NodeId up = parent[q];
    std::vector<NodeId> children;
    for (auto w : boost::make_iterator_range(boost::adjacent_vertices(q, g)))
      if (w != up) children.push_back(w);
    std::sort(children.begin(), children.end());
    const std::size_t k = children.size();
    auto& points = g[q].points;
    if (k < 2 || points.size() < k * options.min_cluster_points) continue;

    // Seeds: the point of q nearest to each child branch.
    std::vector<Eigen::Vector3d> seeds;
    for (auto c : children) {
      const auto nearest = *std::min_element(points.begin(), points.end(), [&](auto a, auto b) {
        return (cloud.positions[a] - g[c].position).squaredNorm() < (cloud.positions[b] - g[c].position).squaredNorm();
      });
      seeds.push_back(cloud.positions[nearest]);
    }
    const auto label = kmeans(cloud.positions, points, seeds, options.kmeans_iterations);

    double sum_r2 = 0.0;
    for (auto c : children) sum_r2 += g[c].radius * g[c].radius;
    const double tau = options.eta * std::sqrt(sum_r2);

    std::vector<std::vector<std::uint32_t>> clusters(k);
    for (std::size_t i = 0; i < points.size(); ++i) clusters[label[i]].push_back(points[i]);
    std::vector<bool> split(k, false);
    std::size_t splits = 0;
    for (std::size_t j = 0; j < k; ++j) {
      if (clusters[j].size() < options.min_cluster_points) continue;
      const Eigen::Vector3d centre = cpc_of(cloud, clusters[j], options.cpc);
      if ((centre - g[q].position).norm() <= tau) continue;
      SkeletonNode sibling;
      sibling.position = centre;
      sibling.points = clusters[j];
      sibling.radius = mean_distance(cloud.positions, sibling.points, centre);
      const NodeId s = add_node(skeleton, sibling);
      keep.push_back(true);
      parent.push_back(up);
      boost::add_edge(s, up, g);
      boost::remove_edge(children[j], q, g);
      boost::add_edge(children[j], s, g);
      parent[children[j]] = s;
      split[j] = true;
      ++splits;
    }
    if (splits == 0) continue;
    added += splits;
    std::vector<std::uint32_t> rest;
    for (std::size_t j = 0; j < k; ++j)
      if (!split[j]) rest.insert(rest.end(), clusters[j].begin(), clusters[j].end());
    std::sort(rest.begin(), rest.end());
    g[q].points = std::move(rest);
    if (splits == k) {
      // Every branch left q: q would be an empty tip. Its remaining points join the nearest sibling.
      keep[q] = false;
      if (!g[q].points.empty()) {
        NodeId nearest = boost::num_vertices(g) - 1;
        double best = std::numeric_limits<double>::infinity();
        for (auto w : boost::make_iterator_range(boost::adjacent_vertices(up, g)))
          if (w >= n0 && (g[w].position - g[q].position).norm() < best) {
            best = (g[w].position - g[q].position).norm();
            nearest = w;
          }
        auto& target = g[nearest].points;
        target.insert(target.end(), g[q].points.begin(), g[q].points.end());
        std::sort(target.begin(), target.end());
        g[q].points.clear();
      }
      boost::clear_vertex(q, g);
    } else if (!g[q].points.empty()) {
      g[q].position = cpc_of(cloud, g[q].points, options.cpc);
      g[q].radius = mean_distance(cloud.positions, g[q].points, g[q].position);
    }
  }
  if (std::find(keep.begin(), keep.end(), false) != keep.end()) compact_nodes(skeleton, keep);
  return added;
}

}  // namespace treeskel
