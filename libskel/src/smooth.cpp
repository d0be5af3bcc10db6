#include "treeskel/smooth.h"

#include "treeskel/error.h"

namespace treeskel {

Skeleton smooth_skeleton(const Skeleton& skeleton, const SmoothOptions& options) {
  return smooth_skeleton(Skeleton(skeleton), options);
}

Skeleton smooth_skeleton(Skeleton&& skeleton, const SmoothOptions& options) {
  if (options.samples_per_edge < 0) throw OptionError("samples per edge must not be negative");
  if (options.tension < 0.0 || options.tension > 1.0) throw OptionError("spline tension must be in [0, 1]");
  auto& g = skeleton.graph;
  const std::size_t n = boost::num_vertices(g);
  Skeleton out;
  out.root = skeleton.root;
  out.offset = skeleton.offset;
  out.noise_points = std::move(skeleton.noise_points);
  out.left_out = skeleton.left_out;
  const int k = options.samples_per_edge;
  const auto order = n == 0 ? std::vector<NodeId>{} : bfs_order(g, skeleton.root);
  // Every node made at once: the input's, then k on each edge from the root outwards.
  SkeletonGraph sized(n + (order.empty() ? 0 : static_cast<std::size_t>(k) * (order.size() - 1)));
  swap_graphs(out.graph, sized);
  for (NodeId v = 0; v < n; ++v) {  // positions and radii stay in `g` for the splines below
    out[v].position = g[v].position;
    out[v].radius = g[v].radius;
    out[v].points = std::move(g[v].points);
  }
  if (n == 0) return out;

  const auto parent = parents_from_root(g, skeleton.root);
  std::vector<int> child_count(n, 0);
  std::vector<NodeId> only_child(n, 0);
  for (NodeId v = 0; v < n; ++v)
    if (v != skeleton.root) {
      ++child_count[parent[v]];
      only_child[parent[v]] = v;
    }
  const double s = (1.0 - options.tension) / 2.0;
  NodeId next = n;
  for (auto v : order) {
    if (v == skeleton.root) continue;
    const NodeId a = parent[v];
    const Eigen::Vector3d& p1 = g[a].position;
    const Eigen::Vector3d& p2 = g[v].position;
    // Where the chain ends (the root, a tip, a fork) the missing neighbour is mirrored, so that
    // evenly spaced collinear nodes give evenly spaced collinear samples.
    const Eigen::Vector3d p0 = a == skeleton.root ? Eigen::Vector3d(2.0 * p1 - p2) : g[parent[a]].position;
    const Eigen::Vector3d p3 = child_count[v] == 1 ? g[only_child[v]].position : Eigen::Vector3d(2.0 * p2 - p1);
    const Eigen::Vector3d m1 = s * (p2 - p0), m2 = s * (p3 - p1);
    NodeId previous = a;
    for (int i = 1; i <= k; ++i) {
      const double t = static_cast<double>(i) / (k + 1), t2 = t * t, t3 = t2 * t;
      const NodeId w = next++;
      out[w].position = (2 * t3 - 3 * t2 + 1) * p1 + (t3 - 2 * t2 + t) * m1 + (-2 * t3 + 3 * t2) * p2 + (t3 - t2) * m2;
      out[w].radius = (1 - t) * g[a].radius + t * g[v].radius;
      boost::add_edge(previous, w, out.graph);
      previous = w;
    }
    boost::add_edge(previous, v, out.graph);
  }
  return out;
}

}  // namespace treeskel
