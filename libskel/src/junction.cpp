#include "treeskel/junction.h"

#include <Eigen/Eigenvalues>

#include <algorithm>

namespace treeskel {

namespace {

struct Line {
  Eigen::Vector3d point, direction;  // direction points away from the fork
};

/// Least-squares line through the positions, oriented along `away`. False for fewer than 2 positions.
bool fit_line(const std::vector<Eigen::Vector3d>& positions, const Eigen::Vector3d& away, Line& line) {
  if (positions.size() < 2) return false;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : positions) mean += p;
  mean /= static_cast<double>(positions.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : positions) cov += (p - mean) * (p - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  Eigen::Vector3d d = eig.eigenvectors().col(2);
  if (d.dot(away) < 0.0) d = -d;
  line = {mean, d};
  return true;
}

}  // namespace

std::size_t relocate_forks(Skeleton& skeleton, double band_width, const JunctionOptions& options) {
  auto& g = skeleton.graph;
  const std::size_t n = boost::num_vertices(g);
  if (n < 4) return 0;
  // Arms scale with the band and with the branch below the fork: a thick stem's junction region is long.
  auto arm_of = [&](double radius) { return options.arm_length > 0.0 ? options.arm_length : std::max(5.0 * band_width, 3.0 * radius); };
  auto skip_of = [&](double radius) { return options.skip > 0.0 ? options.skip : std::max(band_width, radius); };
  std::vector<NodeId> parent = parents_from_root(g, skeleton.root);
  std::vector<std::vector<NodeId>> children(n);
  for (NodeId v = 0; v < n; ++v)
    if (v != skeleton.root) children[parent[v]].push_back(v);
  std::vector<bool> keep(n, true);
  std::size_t moved = 0;

  // Merges node u into fork f: f takes u's points and u's other neighbours.
  auto absorb = [&](NodeId f, NodeId u) {
    auto& pts = g[f].points;
    pts.insert(pts.end(), g[u].points.begin(), g[u].points.end());
    std::sort(pts.begin(), pts.end());
    std::vector<NodeId> others;
    for (auto w : boost::make_iterator_range(boost::adjacent_vertices(u, g)))
      if (w != f) others.push_back(w);
    boost::clear_vertex(u, g);
    for (auto w : others) {
      boost::add_edge(f, w, g);
      if (parent[w] == u) parent[w] = f;
    }
    if (parent[u] != u && std::find(others.begin(), others.end(), parent[u]) != others.end()) parent[f] = parent[u];
    children[f].erase(std::remove(children[f].begin(), children[f].end(), u), children[f].end());
    for (auto w : children[u]) children[f].push_back(w);
    if (parent[u] != u) {
      auto& siblings = children[parent[u]];
      std::replace(siblings.begin(), siblings.end(), u, f);
    }
    keep[u] = false;
  };

  for (NodeId f : bfs_order(g, skeleton.root)) {
    if (!keep[f] || f == skeleton.root || children[f].size() < 2) continue;
    const Eigen::Vector3d origin = g[f].position;
    const double arm = arm_of(g[parent[f]].radius), skip = skip_of(g[parent[f]].radius);
    std::vector<Line> lines;
    // The parent arm, walking down to the root or the previous fork.
    std::vector<Eigen::Vector3d> nodes;
    double along = 0.0;
    for (NodeId u = f; u != skeleton.root;) {
      const NodeId p = parent[u];
      along += (g[p].position - g[u].position).norm();
      if (along > skip + arm) break;
      if (along >= skip) nodes.push_back(g[p].position);
      if (children[p].size() != 1) break;
      u = p;
    }
    Line down;
    const bool has_down = fit_line(nodes, g[parent[f]].position - origin, down);
    if (has_down) lines.push_back(down);
    for (NodeId c : children[f]) {
      nodes.clear();
      along = (g[c].position - origin).norm();
      for (NodeId u = c;;) {
        if (along > skip + arm) break;
        if (along >= skip) nodes.push_back(g[u].position);
        if (children[u].size() != 1) break;
        const NodeId next = children[u].front();
        along += (g[next].position - g[u].position).norm();
        u = next;
      }
      Line up;
      if (fit_line(nodes, g[c].position - origin, up)) lines.push_back(up);
    }
    if (!has_down || lines.size() < 3) continue;  // the parent arm and at least two child arms

    Eigen::Matrix3d a = options.stay_weight * Eigen::Matrix3d::Identity();
    Eigen::Vector3d b = options.stay_weight * origin;
    for (const auto& line : lines) {
      const Eigen::Matrix3d across = Eigen::Matrix3d::Identity() - line.direction * line.direction.transpose();
      a += across;
      b += across * line.point;
    }
    const Eigen::Vector3d target = a.ldlt().solve(b);
    const double limit = options.max_move_radii * g[parent[f]].radius + band_width;
    if (!target.allFinite() || (target - origin).norm() > limit) continue;

    // Nodes now on the wrong side of the fork join it: parent-arm nodes above it, child-arm nodes below.
    for (NodeId u = parent[f]; u != skeleton.root && children[u].size() == 1 && keep[u];) {
      if ((g[u].position - target).dot(down.direction) > 0.5 * band_width) break;
      const NodeId next = parent[u];
      absorb(f, u);
      u = next;
    }
    const std::vector<NodeId> kids = children[f];
    for (const NodeId c : kids) {
      if (children[c].size() != 1) continue;  // never merge a tip or another fork
      const Eigen::Vector3d out = (g[c].position - origin).normalized();
      if ((g[c].position - target).dot(out) <= 0.5 * band_width) absorb(f, c);
    }
    g[f].position = target;
    ++moved;
  }
  if (std::find(keep.begin(), keep.end(), false) != keep.end()) compact_nodes(skeleton, keep);
  return moved;
}

}  // namespace treeskel
