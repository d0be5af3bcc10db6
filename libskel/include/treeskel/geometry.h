/// @file geometry.h
/// Small geometric helpers shared by the stages and the evaluation.
#pragma once

#include <Eigen/Core>

#include <algorithm>

namespace treeskel {

inline constexpr double kPi = 3.14159265358979323846;

/// Volume of the frustum of a cone with end radii `r1`, `r2` and height `length`.
inline double frustum_volume(double r1, double r2, double length) {
  return kPi * length / 3.0 * (r1 * r1 + r1 * r2 + r2 * r2);
}

/// Distance from `p` to the segment [a, b] (to `a` when the segment is a point).
inline double point_segment_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

/// How far `p` lies outside the tube around [a, b] whose radius goes from `ra` at `a` to `rb` at `b`
/// (negative inside).
inline double outside_tube(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b, double ra,
                           double rb) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm() - ((1.0 - t) * ra + t * rb);
}

/// Shortest distance between the segments [a, b] and [c, d] (either may be a point).
inline double segment_segment_distance(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                       const Eigen::Vector3d& d) {
  const Eigen::Vector3d u = b - a, v = d - c, w = a - c;
  const double uu = u.squaredNorm(), vv = v.squaredNorm(), uv = u.dot(v), uw = u.dot(w), vw = v.dot(w);
  const double denom = uu * vv - uv * uv;
  // Nearest points of the two lines, clamped to the first segment; parallel (or point) segments
  // start from a, and the end checks below cover the rest.
  double s = denom > 1e-12 * uu * vv ? std::clamp((uv * vw - vv * uw) / denom, 0.0, 1.0) : 0.0;
  double t = vv > 0.0 ? (uv * s + vw) / vv : 0.0;
  if (t < 0.0 || t > 1.0) {  // the second segment's end is nearest: the first segment's nearest point to it
    t = std::clamp(t, 0.0, 1.0);
    s = uu > 0.0 ? std::clamp((uv * t - uw) / uu, 0.0, 1.0) : 0.0;
  }
  const double best = (a + s * u - (c + t * v)).norm();
  return std::min({best, point_segment_distance(a, c, d), point_segment_distance(b, c, d),
                   point_segment_distance(c, a, b), point_segment_distance(d, a, b)});
}

}  // namespace treeskel
