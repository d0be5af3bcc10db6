#include "treeskel/modeling/base.h"

#include <Eigen/Core>

#include <algorithm>
#include <vector>

namespace treeskel::modeling {

namespace {

/// The share of the root's points whose distance below it sets the base (the rest may be stray).
constexpr double kBaseQuantile = 0.95;
/// The trunk's axis is taken from the root to the first node at least this many root radii up.
constexpr double kAxisRadii = 2.0;
/// The root moves down by at most this many root radii.
constexpr double kMostRadii = 4.0;

}  // namespace

double reach_down(Skeleton& skeleton, const PointCloud& cloud) {
  if (skeleton.node_count() < 2 || skeleton.root >= skeleton.node_count()) return 0.0;
  const auto& g = skeleton.graph;
  const NodeId root = skeleton.root;
  const double radius = g[root].radius;
  const auto& points = g[root].points;
  if (points.size() < 3 || !(radius > 0.0)) return 0.0;
  // Up the thickest path to the first node far enough to show the trunk's direction.
  const auto parent = parents_from_root(g, root);
  NodeId at = root;
  double along = 0.0;
  while (along < kAxisRadii * radius) {
    NodeId next = at;
    double thickest = -1.0;
    for (auto [it, end] = boost::adjacent_vertices(at, g); it != end; ++it)
      if (*it != parent[at] && *it != at && g[*it].radius > thickest) {
        thickest = g[*it].radius;
        next = *it;
      }
    if (next == at) break;  // a tip
    along += (g[next].position - g[at].position).norm();
    at = next;
  }
  const Eigen::Vector3d axis = g[root].position - g[at].position;
  if (!(axis.norm() > 0.0)) return 0.0;
  const Eigen::Vector3d down = axis.normalized();
  std::vector<double> below;
  below.reserve(points.size());
  for (auto i : points) below.push_back((cloud.positions[i] - g[root].position).dot(down));
  const auto k = static_cast<std::size_t>(kBaseQuantile * static_cast<double>(below.size() - 1));
  std::nth_element(below.begin(), below.begin() + static_cast<std::ptrdiff_t>(k), below.end());
  const double move = std::min(below[k], kMostRadii * radius);
  if (!(move > 0.0)) return 0.0;
  skeleton[root].position += move * down;
  return move;
}

}  // namespace treeskel::modeling
