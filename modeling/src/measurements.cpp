#include "treeskel/modeling/measurements.h"

#include "treeskel/error.h"
#include "treeskel/geometry.h"
#include "treeskel/modeling/chains.h"
#include "treeskel/modeling/radii.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <tuple>

namespace treeskel::modeling {

namespace {

constexpr double kSwelling = 1.1;  // a stem this much thicker at breast height than just below swells there
// The skeleton runs along the trunk's axis: a circle whose centre lies farther from it than this
// share of its radius passes close to the axis itself and goes around something else (a whorl of
// branches around a thinner stem, say).
constexpr double kMaxCentreOffset = 0.75;
// A trunk node's own circle widens the slice only when the node lies within this share of its radius
// from its centre: around the node, not an arc of points on one side of it (see measure_tree).
constexpr double kWideningOffset = 0.5;

/// Diameter of a circle fitted to the cloud's points in a slice across the trunk at `at` (along
/// `axis`): the slice spans `half` either side of it (1/13 of the breast height: 1.2 to 1.4 m for
/// 1.3 m, the usual slice of terrestrial-scan inventories) and reaches `reach` from the axis; twice,
/// points more than two rms off the circle are set aside and it is fitted again. None when the
/// circle is unreliable by the same limits as the branch radii's fits (`RadiusOptions`: 8 points, an
/// rms residual within 30% of its radius, 1.5 rad covered) or its centre is farther than 3/4 of its
/// radius from the axis.
std::optional<double> slice_diameter(const PointCloud& cloud, const Eigen::Vector3d& at, const Eigen::Vector3d& axis,
                                     double reach, double half) {
  const RadiusOptions limits;
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
  if (!is_reliable(fit, limits) || fit.centre.norm() > kMaxCentreOffset * fit.radius) return std::nullopt;
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
  std::vector<double> carried(n, 0.0), top_of(n);  // subtree length, subtree's highest node
  const auto order = bfs_order(g, skeleton.root);
  for (auto it = order.rbegin(); it != order.rend(); ++it) {
    top_of[*it] = g[*it].position.dot(up);
    for (NodeId c : t.children[*it]) {
      carried[*it] += carried[c] + (g[c].position - g[*it].position).norm();
      top_of[*it] = std::max(top_of[*it], top_of[c]);
    }
  }
  std::vector<std::size_t> branch(n, 0);
  std::vector<int> branch_order;  // per branch id - 1
  std::vector<std::size_t> position_in_branch(n, 0);
  branch[skeleton.root] = 1;
  branch_order.push_back(0);
  for (NodeId v : order) {
    const auto& kids = t.children[v];
    if (kids.empty()) continue;
    // The thickest child goes on. For the trunk, only among the children that rise at least half
    // as far above the fork as the highest one does: ground or roots left in a scan can fork off
    // the base as thick as the stem, and a limb can be as thick as the leader.
    const double rise = branch[v] == 1 ? top_of[v] - g[v].position.dot(up) : 0.0;
    auto candidate = [&](NodeId c) { return branch[v] != 1 || top_of[c] - g[v].position.dot(up) >= 0.5 * rise; };
    const NodeId main = *std::max_element(kids.begin(), kids.end(), [&](NodeId a, NodeId b) {
      return std::make_tuple(candidate(a), g[a].radius, carried[a]) < std::make_tuple(candidate(b), g[b].radius, carried[b]);
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
    const double volume = frustum_volume(r1, r2, length);
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
  const double half = options.breast_height / 13.0;  // half the slice's height
  // The trunk's diameter from the points of a slice across it at height h above the base.
  auto slice_at = [&](double h) -> std::optional<double> {
    const auto at = reach(base + h);
    if (!at) return std::nullopt;
    const auto [i, f] = *at;
    const double radius = (1.0 - f) * g[trunk[i]].radius + f * g[trunk[i + 1]].radius;
    // The trunk's direction over a quarter of the breast height either side: one skeleton edge
    // can lean by tens of degrees, and a slice that leans is an ellipse.
    const double d = 0.25 * options.breast_height;
    const auto below = reach(base + h - d), above = reach(base + h + d);
    const Eigen::Vector3d low = below ? position(below->first, below->second) : g[trunk.front()].position;
    const Eigen::Vector3d high = above ? position(above->first, above->second) : g[trunk.back()].position;
    if (!((high - low).norm() > 0.0)) return std::nullopt;
    // Twice the radius keeps the slice off nearby branches: the model's radius first. It can be far
    // too small where many side chains share the trunk's cross section (ground left at the base, a
    // crowded leader), and a slice that misses the bark fits nothing; only then does the circle
    // fitted to the points of a trunk node within a slice's height widen it, if that is larger and
    // reliable and the node lies in the inner half of it (its centre within kWideningOffset of its
    // radius). A slice that fits the bark is not widened: more reach only takes in the branches
    // around it. (A node of TreeLS's spruce whose outer points went to twigs grown by --complete-all
    // kept an arc of 30 points, a circle of 0.39 m centred 0.28 m off the trunk of 0.12 m; with
    // --complete, a node moved by the limbs' smoothing came to lie inside a 0.23 m circle of 33
    // points. The slices they widened took in the branches: DBH 0.78 m and 0.59 m instead of 0.35 m.)
    const Eigen::Vector3d centre = position(i, f), axis = (high - low).normalized();
    if (const auto narrow = slice_diameter(*cloud, centre, axis, 2.0 * radius, half)) return narrow;
    double wide = radius;
    for (NodeId v : trunk)
      if (std::abs(g[v].position.dot(up) - base - h) <= 2.0 * half)
        if (const RadiusMeasurement fit = measure_node_radius(skeleton, *cloud, v);
            fit.weight > 0.0 && fit.offset <= kWideningOffset * fit.radius)
          wide = std::max(wide, fit.radius);
    if (wide == radius) return std::nullopt;
    return slice_diameter(*cloud, centre, axis, 2.0 * wide, half);
  };
  if (const auto at = reach(target)) {
    const auto [i, f] = *at;
    m.dbh = 2.0 * ((1.0 - f) * g[trunk[i]].radius + f * g[trunk[i + 1]].radius);
    m.dbh_source = DbhSource::model;
    m.dbh_height = options.breast_height;
    if (cloud && options.dbh_from_points) {
      // The slice under the breast-height one: where the stem swells at breast height (more than
      // kSwelling thicker than just below: a fork, a branch, a burl; a healthy stem narrows upward)
      // or no reliable circle fits there (a fork, or the slice spans a limb), the diameter is taken
      // there, as foresters measure.
      const double lower = options.breast_height - 2.0 * half;
      const auto measured = slice_at(options.breast_height), under = slice_at(lower);
      if (measured) {
        m.dbh = *measured;
        m.dbh_source = DbhSource::points;
        if (under && *measured > kSwelling * *under) {
          m.dbh = *under;
          m.dbh_height = lower;
        }
      } else if (under) {
        m.dbh = *under;
        m.dbh_source = DbhSource::points;
        m.dbh_height = lower;
        m.dbh_unfit_at_breast_height = true;
      }
    }
  }
  return m;
}

std::string dbh_note(const TreeMeasurements& m) {
  if (!m.dbh) return "";
  if (m.dbh_source != DbhSource::points) return " (from the model)";
  if (m.dbh_height == m.breast_height) return " (fitted to the points)";
  std::ostringstream s;
  s << " (fitted to the points at " << std::setprecision(3) << m.dbh_height
    << (m.dbh_unfit_at_breast_height ? ", where none fits at " : ", below a swelling at ") << m.breast_height << ")";
  return s.str();
}

}  // namespace treeskel::modeling
