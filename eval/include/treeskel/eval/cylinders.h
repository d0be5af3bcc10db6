/// @file cylinders.h
/// Point clouds sampled on the surface of a set of (tapered) cylinders: the synthetic scans whose true
/// skeleton is known.
#pragma once

#include "treeskel/point_cloud.h"

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <vector>

namespace treeskel::eval {

/// A truncated cone from `a` (radius `radius_a`) to `b` (radius `radius_b`).
struct Cylinder {
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::UnitZ();
  double radius_a = 0.1, radius_b = 0.1;
};

struct SurfaceSampling {
  std::size_t points = 10000;
  std::uint64_t seed = 1;
  double noise = 0.0;  ///< standard deviation of Gaussian noise along the surface normal
  /// When set, only the side of each cylinder facing this direction is kept (one scanner's view).
  std::optional<Eigen::Vector3d> facing;
  /// When set, a scanner standing at this point: only the points it sees are kept (their side faces it
  /// and no cylinder lies between), each with probability cos(incidence) x (d_near / d)^2, where d is
  /// the point's distance from the scanner and d_near the distance from the scanner to the nearest
  /// cylinder's box: a scanner's beams part with distance and meet the bark obliquely at its sides, so
  /// far and grazing surfaces get fewer points. Must lie outside every cylinder.
  std::optional<Eigen::Vector3d> viewpoint;
};

/// Points spread evenly by area on the lateral surfaces, without the points that fall inside another
/// cylinder (so there are no points inside the wood at junctions). Deterministic for a seed and
/// independent of the thread count.
/// @throws treeskel::Error if the surfaces are almost entirely hidden inside each other (or from the
/// viewpoint).
PointCloud sample_cylinders(const std::vector<Cylinder>& cylinders, const SurfaceSampling& sampling);

/// Distance from `p` to the axis segment of `c`.
double distance_to_axis(const Cylinder& c, const Eigen::Vector3d& p);

/// Radius of `c` at the projection of `p` on its axis, and whether the projection is inside [a, b].
bool inside(const Cylinder& c, const Eigen::Vector3d& p);

}  // namespace treeskel::eval
