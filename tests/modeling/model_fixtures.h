// Small skeletons with radii, for the modeling tests.
#pragma once

#include "treeskel/point_cloud.h"
#include "treeskel/skeleton.h"

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <vector>

namespace treeskel::test {

/// Adds a straight run of `steps` edges from node `from` to `to_position`, radii interpolated.
inline NodeId add_run(Skeleton& s, NodeId from, const Eigen::Vector3d& to_position, double to_radius, int steps) {
  const Eigen::Vector3d start = s[from].position;
  const double r0 = s[from].radius;
  NodeId prev = from;
  for (int i = 1; i <= steps; ++i) {
    const double t = static_cast<double>(i) / steps;
    SkeletonNode node;
    node.position = (1.0 - t) * start + t * to_position;
    node.radius = (1.0 - t) * r0 + t * to_radius;
    const NodeId v = add_node(s, node);
    boost::add_edge(prev, v, s.graph);
    prev = v;
  }
  return prev;
}

/// A skeleton of its root alone, at the origin with `radius`.
inline Skeleton lone_root(double radius) {
  Skeleton s;
  SkeletonNode root;
  root.radius = radius;
  s.root = add_node(s, root);
  return s;
}

/// Adds `count` points on a circle of radius `r` around node `v`, across the direction `along`, to
/// `cloud`, and makes them the node's points.
inline void add_ring(Skeleton& s, PointCloud& cloud, NodeId v, const Eigen::Vector3d& along, double r, int count = 12) {
  const Eigen::Vector3d u = along.unitOrthogonal(), w = along.normalized().cross(u);
  for (int k = 0; k < count; ++k) {
    const double a = 2.0 * 3.14159265358979323846 * k / count;
    s[v].points.push_back(static_cast<std::uint32_t>(cloud.size()));
    cloud.positions.push_back(s[v].position + r * (std::cos(a) * u + std::sin(a) * w));
  }
}

/// A vertical chain from the origin to (0, 0, length), constant radius.
inline Skeleton straight(double length, double radius, int steps = 20) {
  Skeleton s = lone_root(radius);
  add_run(s, s.root, Eigen::Vector3d(0, 0, length), radius, steps);
  return s;
}

/// A Y: a trunk of `trunk_radius` from the origin to (0, 0, 1), then two arms of length 1 at
/// +-`half_angle` from the vertical whose radii obey Leonardo's rule (r^2 = trunk^2 / 2).
inline Skeleton y_shape(double trunk_radius, double half_angle = 0.6, int steps = 20) {
  Skeleton s = straight(1.0, trunk_radius, steps);
  const NodeId fork = static_cast<NodeId>(s.node_count() - 1);
  const double r = trunk_radius / std::sqrt(2.0);
  for (double sign : {-1.0, 1.0}) {
    const Eigen::Vector3d tip(sign * std::sin(half_angle), 0.0, 1.0 + std::cos(half_angle));
    // The first node of each arm already has the arm's radius.
    SkeletonNode first;
    first.position = s[fork].position + (tip - s[fork].position) / steps;
    first.radius = r;
    const NodeId v = add_node(s, first);
    boost::add_edge(fork, v, s.graph);
    add_run(s, v, tip, r, steps - 1);
  }
  return s;
}

}  // namespace treeskel::test
