/// @file stems.h
/// Stems of a plot: the points in a slice above the ground grouped by proximity in plan, the slice cut
/// into layers, and a group kept as a stem when a circle fits its points (a trunk seen from one side
/// or all round) in enough layers and those circles agree; branches leaving in some layers, or a
/// shrub beside the trunk in others, do not hide it. The rest is left to the segmentation.
#pragma once

#include "treeskel/forest/ground.h"
#include "treeskel/point_cloud.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace treeskel::forest {

/// A circle in plan: the least-squares (geometric) circle of the points, after an algebraic start.
struct Circle {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius = 0.0;
  double rms = 0.0;          ///< root mean square of the inliers' distances to the circle
  std::size_t inliers = 0;   ///< points within the final band around the circle
  bool ok = false;           ///< false when the points do not define a circle
};

/// Fits a circle to `points`, re-fitting twice on the points within max(3 median deviations,
/// `min_band`) of the previous circle, so that a branch stub or a leaf beside the trunk does not pull it.
Circle fit_circle(const std::vector<Eigen::Vector2d>& points, double min_band = 0.01);

/// The circle most of `points` lie on, even among others (a trunk's ring beside branches): of 200
/// circles through three of the points (deterministic for `seed`), the one with the most points
/// within 1 cm + 2% of its radius, less two for each point well inside it (a trunk's ring is hollow),
/// re-fitted by fit_circle on its points. `ok` is false when no circle
/// of a radius in [min_radius, max_radius] holds three points.
Circle find_circle(const std::vector<Eigen::Vector2d>& points, double min_radius, double max_radius, std::uint64_t seed = 0);

struct StemOptions {
  double slice_bottom = 0.3;  ///< the slice searched for stems, in height above the ground
  double slice_top = 1.8;
  int layers = 6;             ///< the slice is cut into this many layers ...
  int min_layers = 3;         ///< ... and a stem is round in at least this many of them, alike
  double gap = 0.1;           ///< points closer than this in plan are one group
  std::size_t min_points = 30;
  double min_radius = 0.02, max_radius = 1.0;
  double max_rms = 0.05;      ///< a layer's circle: inlier RMS at most this share of its radius (plus 1 cm)
  double min_inliers = 0.5;   ///< ... holding at least this share of the layer's points
  double merge = 0.3;         ///< stems whose centres are closer than this (plus their radii) are one
};

struct Stem {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  ///< in plan, local frame: the mean of its layers' circles
  double ground = 0.0;   ///< the terrain's elevation under the centre
  double radius = 0.0;   ///< the median of its layers' circles
  std::size_t points = 0;  ///< slice points of the group
};

/// The stems of the cloud, in order of their centres (x, then y), so results do not depend on threads.
std::vector<Stem> find_stems(const PointCloud& cloud, const Ground& ground, const StemOptions& options = {});

}  // namespace treeskel::forest
