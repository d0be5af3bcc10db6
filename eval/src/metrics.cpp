#include "treeskel/eval/metrics.h"

#include "treeskel/geometry.h"

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace treeskel::eval {

namespace {

Eigen::Vector3d world(const Skeleton& s, NodeId v) { return s[v].position + s.offset; }

std::vector<Eigen::Vector3d> nodes_of_degree(const Skeleton& s, bool branch) {
  std::vector<Eigen::Vector3d> out;
  for (NodeId v = 0; v < s.node_count(); ++v) {
    const auto d = boost::degree(v, s.graph);
    if (branch ? d >= 3 : d == 1) out.push_back(world(s, v));
  }
  return out;
}

}  // namespace

double skeleton_point_deviation(const Skeleton& from, const Skeleton& to) {
  if (from.node_count() == 0 || to.node_count() == 0) return std::numeric_limits<double>::infinity();
  double sum = 0.0;
  if (to.edge_count() == 0) {  // a lone node: distances to it
    for (NodeId v = 0; v < from.node_count(); ++v) {
      double best = std::numeric_limits<double>::infinity();
      for (NodeId w = 0; w < to.node_count(); ++w) best = std::min(best, point_segment_distance(world(from, v), world(to, w), world(to, w)));
      sum += best;
    }
    return sum / static_cast<double>(from.node_count());
  }
  // Exact point-to-segment distances through CGAL's AABB tree.
  using Kernel = CGAL::Simple_cartesian<double>;
  using Segment = Kernel::Segment_3;
  using Primitive = CGAL::AABB_segment_primitive<Kernel, std::vector<Segment>::const_iterator>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
  auto point = [](const Eigen::Vector3d& p) { return Kernel::Point_3(p.x(), p.y(), p.z()); };
  std::vector<Segment> segments;
  for (auto e : boost::make_iterator_range(boost::edges(to.graph))) {
    const auto a = world(to, boost::source(e, to.graph)), b = world(to, boost::target(e, to.graph));
    if ((a - b).norm() > 0.0) segments.emplace_back(point(a), point(b));
  }
  if (segments.empty()) segments.emplace_back(point(world(to, 0)), point(world(to, 0) + Eigen::Vector3d(1e-12, 0, 0)));
  Tree tree(segments.cbegin(), segments.cend());
  tree.accelerate_distance_queries();
  for (NodeId v = 0; v < from.node_count(); ++v) sum += std::sqrt(tree.squared_distance(point(world(from, v))));
  return sum / static_cast<double>(from.node_count());
}

std::vector<int> min_cost_assignment(const Eigen::MatrixXd& cost) {
  const int rows = static_cast<int>(cost.rows()), cols = static_cast<int>(cost.cols());
  if (rows == 0 || cols == 0) return std::vector<int>(rows, -1);
  if (rows > cols) {  // solve the transpose and invert the answer
    const auto by_col = min_cost_assignment(cost.transpose());
    std::vector<int> by_row(rows, -1);
    for (int c = 0; c < cols; ++c)
      if (by_col[c] >= 0) by_row[by_col[c]] = c;
    return by_row;
  }
  // Shortest augmenting paths with potentials (Kuhn-Munkres); 1-based with a dummy column 0.
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(rows + 1, 0.0), v(cols + 1, 0.0);
  std::vector<int> match(cols + 1, 0), way(cols + 1, 0);  // match[c]: row assigned to column c
  for (int r = 1; r <= rows; ++r) {
    match[0] = r;
    int c0 = 0;
    std::vector<double> slack(cols + 1, inf);
    std::vector<bool> used(cols + 1, false);
    do {
      used[c0] = true;
      const int r0 = match[c0];
      double delta = inf;
      int c1 = 0;
      for (int c = 1; c <= cols; ++c) {
        if (used[c]) continue;
        const double reduced = cost(r0 - 1, c - 1) - u[r0] - v[c];
        if (reduced < slack[c]) {
          slack[c] = reduced;
          way[c] = c0;
        }
        if (slack[c] < delta) {
          delta = slack[c];
          c1 = c;
        }
      }
      for (int c = 0; c <= cols; ++c) {
        if (used[c]) {
          u[match[c]] += delta;
          v[c] -= delta;
        } else {
          slack[c] -= delta;
        }
      }
      c0 = c1;
    } while (match[c0] != 0);
    do {
      const int c1 = way[c0];
      match[c0] = match[c1];
      c0 = c1;
    } while (c0 != 0);
  }
  std::vector<int> by_row(rows, -1);
  for (int c = 1; c <= cols; ++c)
    if (match[c] > 0) by_row[match[c] - 1] = c - 1;
  return by_row;
}

std::size_t matched_within(const std::vector<Eigen::Vector3d>& truth, const std::vector<Eigen::Vector3d>& predicted,
                           double tau) {
  if (truth.empty() || predicted.empty()) return 0;
  Eigen::MatrixXd cost(truth.size(), predicted.size());
  for (std::size_t i = 0; i < truth.size(); ++i)
    for (std::size_t j = 0; j < predicted.size(); ++j) cost(i, j) = (truth[i] - predicted[j]).norm();
  const auto assignment = min_cost_assignment(cost);
  std::size_t matched = 0;
  for (std::size_t i = 0; i < truth.size(); ++i)
    if (assignment[i] >= 0 && cost(i, assignment[i]) < tau) ++matched;
  return matched;
}

Metrics evaluate(const Skeleton& predicted, const Skeleton& truth, const MetricOptions& options) {
  Metrics m;
  m.spd = skeleton_point_deviation(truth, predicted);
  m.reverse_spd = skeleton_point_deviation(predicted, truth);
  const auto tb = nodes_of_degree(truth, true), pb = nodes_of_degree(predicted, true);
  const auto te = nodes_of_degree(truth, false), pe = nodes_of_degree(predicted, false);
  m.truth_branch_points = tb.size();
  m.predicted_branch_points = pb.size();
  m.truth_endpoints = te.size();
  m.predicted_endpoints = pe.size();
  m.matched_branch_points = matched_within(tb, pb, options.tau);
  m.matched_endpoints = matched_within(te, pe, options.tau);
  auto ratio = [](std::size_t a, std::size_t b) { return b == 0 ? (a == 0 ? 1.0 : 0.0) : double(a) / double(b); };
  m.bpc = tb.empty() ? 1.0 : ratio(m.matched_branch_points, tb.size());
  m.epc = te.empty() ? 1.0 : ratio(m.matched_endpoints, te.size());
  m.bp_precision = pb.empty() ? (tb.empty() ? 1.0 : 0.0) : ratio(m.matched_branch_points, pb.size());
  m.ep_precision = pe.empty() ? (te.empty() ? 1.0 : 0.0) : ratio(m.matched_endpoints, pe.size());
  m.components = predicted.node_count() == 0 ? 0 : count_components(predicted.graph);
  m.cycles = predicted.edge_count() + m.components - predicted.node_count();
  return m;
}

}  // namespace treeskel::eval
