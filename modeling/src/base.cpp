#include "treeskel/modeling/base.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <limits>
#include <vector>

namespace treeskel::modeling {

namespace {

/// The share of the root's points whose distance below it sets the base (the rest may be stray).
constexpr double kBaseQuantile = 0.95;
/// The trunk's axis is the line through the nodes of the thickest path up to this many root radii
/// from the root.
constexpr double kAxisRadii = 6.0;
/// Of the root's points, only those within this many root radii of the trunk's axis count: the
/// trunk's own bark, not the ground or the roots around it. (Counted too, ground points a metre to the
/// side of TreeLS's spruce, whose axis near the root leans, reached 0.4 m down that axis and took the
/// base 0.4 m below the lowest point of the scan.)
constexpr double kNearAxisRadii = 2.0;
/// The root moves by at most this many root radii.
constexpr double kMostRadii = 4.0;
/// The trunk's axis must point down within this angle (its cosine) of the way from the skeleton's
/// centre to its root: the tree stands above its root, and a base that wanders sideways (roots,
/// ground) gives no axis to go down.
constexpr double kLeastDownCosine = 0.7071;

}  // namespace

double reach_down(Skeleton& skeleton, const PointCloud& cloud) {
  if (skeleton.node_count() < 2 || skeleton.root >= skeleton.node_count()) return 0.0;
  const auto& g = skeleton.graph;
  const NodeId root = skeleton.root;
  const double radius = g[root].radius;
  const auto& points = g[root].points;
  if (points.size() < 3 || !(radius > 0.0)) return 0.0;
  // The trunk's nodes: up the thickest path from the root (not the root itself, which may lie beside
  // the axis).
  const auto parent = parents_from_root(g, root);
  std::vector<Eigen::Vector3d> trunk;
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
    trunk.push_back(g[at].position);
  }
  if (trunk.size() < 3 || !(along > 0.0)) return 0.0;
  // Its axis: the principal direction of those nodes, pointing down (from the far end to the root).
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& p : trunk) centre += p;
  centre /= static_cast<double>(trunk.size());
  Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
  for (const auto& p : trunk) spread += (p - centre) * (p - centre).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(spread);
  Eigen::Vector3d down = eigen.eigenvectors().col(2);
  if (down.dot(g[root].position - trunk.back()) < 0.0) down = -down;
  Eigen::Vector3d middle = Eigen::Vector3d::Zero();
  for (NodeId v = 0; v < skeleton.node_count(); ++v) middle += g[v].position;
  middle /= static_cast<double>(skeleton.node_count());
  const Eigen::Vector3d fall = g[root].position - middle;
  if (!(fall.norm() > 0.0) || down.dot(fall.normalized()) < kLeastDownCosine) return 0.0;
  // Where the root's points near the axis end along it; the root goes onto the axis there, never
  // up, and not below the lowest of those points taken the way the tree falls from its centre to
  // its root (a leaning axis meets the ground lower beside the trunk than under it).
  std::vector<double> below;
  below.reserve(points.size());
  const Eigen::Vector3d way = fall.normalized();
  double lowest = -std::numeric_limits<double>::infinity();
  for (auto i : points) {
    const Eigen::Vector3d p = cloud.positions[i] - centre;
    const double d = p.dot(down);
    if ((p - d * down).norm() > kNearAxisRadii * radius) continue;
    below.push_back(d);
    lowest = std::max(lowest, p.dot(way));
  }
  if (below.size() < 3) return 0.0;
  const auto k = static_cast<std::size_t>(kBaseQuantile * static_cast<double>(below.size() - 1));
  std::nth_element(below.begin(), below.begin() + static_cast<std::ptrdiff_t>(k), below.end());
  const double floor = lowest / down.dot(way);  // the level on the axis as low as that point
  const double level = std::max(std::min(below[k], floor), (g[root].position - centre).dot(down));
  const Eigen::Vector3d base = centre + level * down;
  const Eigen::Vector3d move = base - g[root].position;
  if (!(move.norm() > 0.0) || move.norm() > kMostRadii * radius) return 0.0;
  skeleton[root].position = base;
  return move.norm();
}

}  // namespace treeskel::modeling
