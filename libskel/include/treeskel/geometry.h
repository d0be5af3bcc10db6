/// @file geometry.h
/// Small geometric helpers shared by the stages and the evaluation.
#pragma once

#include <Eigen/Core>

#include <algorithm>

namespace treeskel {

/// Distance from `p` to the segment [a, b] (to `a` when the segment is a point).
inline double point_segment_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

}  // namespace treeskel
