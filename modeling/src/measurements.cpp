#include "treeskel/modeling/measurements.h"

#include "treeskel/error.h"
#include "treeskel/modeling/chains.h"
#include "treeskel/modeling/radii.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace treeskel::modeling {

namespace {

/// Diameter of a circle fitted to the cloud's points in a slice across the trunk at `at` (along
/// `axis`): the slice spans breast height ± 1/13 of it (1.2 to 1.4 m for 1.3 m, the usual slice of
/// terrestrial-scan inventories) and reaches twice the modelled `radius` from the axis; twice, points
/// more than two rms off the circle are set aside and it is fitted again. None when the circle is
/// unreliable by the same limits as the branch radii's fits (`RadiusOptions`: 8 points, an rms
/// residual within 30% of its radius, 1.5 rad covered) or its centre is farther than its radius
/// from the axis.
std::optional<double> slice_diameter(const PointCloud& cloud, const Eigen::Vector3d& at, const Eigen::Vector3d& axis,
                                     double radius, double breast_height) {
  const RadiusOptions limits;
  const double half = breast_height / 13.0, reach = 2.0 * radius;
  const Eigen::Vector3d u = axis.unitOrthogonal(), w = axis.cross(u);
  std::vector<Eigen::Vector2d> slice;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d d = cloud.positions[i] - at;
    const double along = d.dot(axis);
    if (std::abs(along) > half) continue;
    const Eigen::Vector2d q(d.dot(u), d.dot(w));
    if (q.norm() <= reach) slice.push_back(q);
  }
  if (slice.size() < limits.min_points) return std::nullopt;
  CircleFit fit = fit_circle(slice);
  // A twig, a leaf or ghost points off the trunk's circle are set aside.
  for (int round = 0; round < 2 && fit.radius > 0.0; ++round) {
    std::vector<Eigen::Vector2d> kept;
    for (const auto& q : slice)
      if (std::abs((q - fit.centre).norm() - fit.radius) <= 2.0 * fit.rms) kept.push_back(q);
    if (kept.size() < limits.min_points || kept.size() == slice.size()) break;
    slice = std::move(kept);
    fit = fit_circle(slice);
  }
  if (!is_reliable(fit, limits) || fit.centre.norm() > fit.radius) return std::nullopt;
  return 2.0 * fit.radius;
}

}  // namespace

TreeMeasurements measure_tree(const Skeleton& skeleton, const PointCloud* cloud, const MeasureOptions& options) {
  if (!(options.up.norm() > 0.0)) throw OptionError("the up direction must not be zero");
  if (!(options.breast_height > 0.0)) throw OptionError("the breast height must be positive");
  const ChainTree t = build_chains(skeleton);
  const auto& g = skeleton.graph;
  const std::size_t n = boost::num_vertices(g);
  const Eigen::Vector3d up = options.up.normalized();
  constexpr double kPi = 3.14159265358979323846;

  TreeMeasurements m;
  m.breast_height = options.breast_height;
  double base = std::numeric_limits<double>::infinity(), top = -base;
  for (NodeId v = 0; v < n; ++v) {
    top = std::max(top, g[v].position.dot(up));
    if (cloud)
      for (auto i : g[v].points) {
        const double h = cloud->positions[i].dot(up);
        base = std::min(base, h);
        top = std::max(top, h);
      }
  }
  if (!std::isfinite(base)) base = g[skeleton.root].position.dot(up);
  m.height = top - base;

  // Branches: at every fork the thickest child (then the one carrying the longest subtree) goes on.
  std::vector<double> carried(n, 0.0);
  const auto order = bfs_order(g, skeleton.root);
  for (auto it = order.rbegin(); it != order.rend(); ++it)
    for (NodeId c : t.children[*it]) carried[*it] += carried[c] + (g[c].position - g[*it].position).norm();
  std::vector<std::size_t> branch(n, 0);
  std::vector<int> branch_order;  // per branch id - 1
  std::vector<std::size_t> position_in_branch(n, 0);
  branch[skeleton.root] = 1;
  branch_order.push_back(0);
  for (NodeId v : order) {
    const auto& kids = t.children[v];
    if (kids.empty()) continue;
    const NodeId main = *std::max_element(kids.begin(), kids.end(), [&](NodeId a, NodeId b) {
      return std::make_pair(g[a].radius, carried[a]) < std::make_pair(g[b].radius, carried[b]);
    });
    for (NodeId c : kids) {
      if (c == main) {
        branch[c] = branch[v];
        position_in_branch[c] = position_in_branch[v] + 1;
      } else {
        branch_order.push_back(branch_order[branch[v] - 1] + 1);
        branch[c] = branch_order.size();
        position_in_branch[c] = 1;
      }
    }
  }
  for (int k : branch_order) {
    if (static_cast<std::size_t>(k) >= m.branches_by_order.size()) m.branches_by_order.resize(static_cast<std::size_t>(k) + 1, 0);
    ++m.branches_by_order[static_cast<std::size_t>(k)];
  }

  // Cylinders, one per edge, parents first; the radius keeps the frustum's volume.
  std::vector<std::size_t> cylinder_to(n, 0);  // id of the cylinder ending at each node
  for (NodeId v : order) {
    if (v == skeleton.root) continue;
    const NodeId p = t.parent[v];
    const Eigen::Vector3d d = g[v].position - g[p].position;
    const double length = d.norm();
    const double r1 = g[p].radius, r2 = g[v].radius;
    const double volume = kPi * length / 3.0 * (r1 * r1 + r1 * r2 + r2 * r2);
    m.volume += volume;
    m.length += length;
    if (branch[v] == 1) m.trunk_length += length;
    QsmCylinder c;
    c.id = m.cylinders.size() + 1;
    c.parent = cylinder_to[p];
    c.branch = branch[v];
    c.order = branch_order[branch[v] - 1];
    c.position = position_in_branch[v];
    c.start = g[p].position + skeleton.offset;
    c.axis = length > 0.0 ? Eigen::Vector3d(d / length) : up;
    c.length = length;
    c.radius = std::sqrt((r1 * r1 + r1 * r2 + r2 * r2) / 3.0);
    cylinder_to[v] = c.id;
    m.cylinders.push_back(c);
  }

  // DBH: where the trunk passes breast height above the base.
  std::vector<NodeId> trunk{skeleton.root};
  for (bool more = true; more;) {
    more = false;
    for (NodeId c : t.children[trunk.back()])
      if (branch[c] == 1) {
        trunk.push_back(c);
        more = true;
        break;
      }
  }
  // Where the trunk first reaches height h: segment and fraction (none when it never does).
  auto reach = [&](double h) -> std::optional<std::pair<std::size_t, double>> {
    for (std::size_t i = 0; i + 1 < trunk.size(); ++i) {
      const double h0 = g[trunk[i]].position.dot(up), h1 = g[trunk[i + 1]].position.dot(up);
      if ((h0 - h) * (h1 - h) <= 0.0 && h0 != h1) return std::make_pair(i, (h - h0) / (h1 - h0));
    }
    return std::nullopt;
  };
  auto position = [&](std::size_t i, double f) {
    return Eigen::Vector3d((1.0 - f) * g[trunk[i]].position + f * g[trunk[i + 1]].position);
  };
  const double target = base + options.breast_height;
  if (const auto at = reach(target)) {
    const auto [i, f] = *at;
    const double radius = (1.0 - f) * g[trunk[i]].radius + f * g[trunk[i + 1]].radius;
    m.dbh = 2.0 * radius;
    m.dbh_source = DbhSource::model;
    if (cloud && options.dbh_from_points) {
      // The trunk's direction over a quarter of the breast height either side: one skeleton edge
      // can lean by tens of degrees, and a slice that leans is an ellipse.
      const double d = 0.25 * options.breast_height;
      const auto below = reach(target - d), above = reach(target + d);
      const Eigen::Vector3d low = below ? position(below->first, below->second) : g[trunk.front()].position;
      const Eigen::Vector3d high = above ? position(above->first, above->second) : g[trunk.back()].position;
      const Eigen::Vector3d centre = position(i, f);  // the cloud's frame too
      if ((high - low).norm() > 0.0)
        if (const auto measured = slice_diameter(*cloud, centre, (high - low).normalized(), radius, options.breast_height)) {
          m.dbh = *measured;
          m.dbh_source = DbhSource::points;
        }
    }
  }
  return m;
}

}  // namespace treeskel::modeling
