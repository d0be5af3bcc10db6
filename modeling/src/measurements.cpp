#include "treeskel/modeling/measurements.h"

#include "treeskel/error.h"
#include "treeskel/modeling/chains.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace treeskel::modeling {

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
  const double target = base + options.breast_height;
  NodeId v = skeleton.root;
  while (true) {
    NodeId next = v;
    for (NodeId c : t.children[v])
      if (branch[c] == 1) next = c;
    if (next == v) break;
    const double h0 = g[v].position.dot(up), h1 = g[next].position.dot(up);
    if ((h0 - target) * (h1 - target) <= 0.0 && h0 != h1) {
      const double f = (target - h0) / (h1 - h0);
      m.dbh = 2.0 * ((1.0 - f) * g[v].radius + f * g[next].radius);
      break;
    }
    v = next;
  }
  return m;
}

}  // namespace treeskel::modeling
