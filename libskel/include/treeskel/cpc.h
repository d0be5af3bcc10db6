/// @file cpc.h
/// Cylindrical prior constraint (Fu et al. 2020, section IV.C, eq. 3-7): a node is moved to the point
/// that minimises the sum of distances to its points plus a weighted variance of those distances, so
/// that on a half-scanned branch it slides from the scanned side onto the branch axis.
///
/// Scale: as printed, λ = m²·μ (eq. 7) depends on the number of points and on the units. We minimise
/// the same objective divided by m, with λ = w / μ, μ the current mean distance:
///     F(v) = mean_i d_i + (w / μ) · var_i d_i,   d_i = |v - x_i|,
/// which is free of units and point counts. On a half cylinder of radius r the minimiser sits about
/// 3.4·r / w from the axis (the L1 term pulls toward the scanned side), so w = 100 leaves ~3% of r.
/// Minimised by Newton's method with a step-halving line search (3×3 systems, a few passes).
///
/// Guards the paper does not have, because the variance term alone is minimised by the centre of any
/// sphere-like patch, which is far off the branch at junctions: a node moves only within the plane
/// across its branch (the cross-section the prior speaks of), by at most `max_shift` mean distances,
/// and only where its points then really look like a cylinder slice (relative spread of the distances
/// at most `max_spread`); otherwise it keeps its L1-median. Branch nodes are left to the refinement.
#pragma once

#include "treeskel/point_cloud.h"
#include "treeskel/skeleton.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace treeskel {

struct CpcOptions {
  double weight = 100.0;       ///< w: weight of the equal-distance term (0 gives the L1-median)
  int max_iterations = 50;     ///< Newton steps at most
  double tolerance = 1e-6;     ///< stop when a step is shorter than this times the mean distance
  std::size_t min_points = 8;  ///< nodes with fewer points keep their position
  std::size_t max_points = 4096;  ///< larger sets are thinned to about this many at an even stride
  /// A result farther than this many mean distances from the start is refused, and the node keeps
  /// its position.
  double max_shift = 1.5;
  /// A result where the distances' standard deviation exceeds this share of their mean is refused:
  /// the points are not a cylinder slice (a junction, a tuft of noise).
  double max_spread = 0.25;
};

/// F(v) above for `points` (λ = w / μ(v) held fixed) with its gradient and Hessian in v: one evaluation
/// of the Newton steps `cpc_centre` takes. Zero for no points.
struct CpcObjective {
  double value = 0.0;
  double mean = 0.0;  ///< μ(v), the mean distance
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
  Eigen::Matrix3d hessian = Eigen::Matrix3d::Zero();
};
CpcObjective cpc_objective(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& v, double weight);

/// The CPC centre of `positions[i]`, i in [first, last), starting from `start`. With a non-zero
/// `axis`, the centre moves only in the plane through `start` perpendicular to it.
Eigen::Vector3d cpc_centre(const std::vector<Eigen::Vector3d>& positions, const std::uint32_t* first,
                           const std::uint32_t* last, const Eigen::Vector3d& start, const CpcOptions& options = {},
                           const Eigen::Vector3d& axis = Eigen::Vector3d::Zero());

/// Moves every node that is not a branch node and has enough points to its CPC centre, across the
/// direction of its branch (parent to child), and sets every radius to the mean distance of the node's
/// points (eq. 9). Parallel over nodes; deterministic.
void recentre_nodes(Skeleton& skeleton, const PointCloud& cloud, const CpcOptions& options = {});

}  // namespace treeskel
