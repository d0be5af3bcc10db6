/// @file ground.h
/// The ground of a plot scan: a terrain model on a grid by the progressive morphological filter
/// (Zhang et al., IEEE TGRS 2003), the points on it, and every point's height above it.
/// Plots are taken as z-up and in metres; the defaults are distances in metres.
#pragma once

#include "treeskel/point_cloud.h"

#include <cstdint>
#include <vector>

namespace treeskel::forest {

struct GroundOptions {
  double cell = 0.5;  ///< terrain grid step
  /// The filter opens the lowest-point surface with square windows of 3, 5, 9, 17, ... cells up to this
  /// width: anything narrower than it (a stem, a crown with no ground seen below it) is lifted off.
  double max_window = 16.0;
  double slope = 0.15;          ///< rise over run of the terrain's bumps kept (not of its slope: the opening keeps that)
  double initial_threshold = 0.3;  ///< height over the opened surface still taken as ground, smallest window
  double max_threshold = 1.0;      ///< ... the most it grows to with the window (slopes are kept by the opening itself)
  double tolerance = 0.15;  ///< points within this height of the terrain are ground
};

/// A terrain model: elevations on a grid in the cloud's local frame, cell (i, j) centred at
/// origin + ((i + 0.5) cell, (j + 0.5) cell).
struct Terrain {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  double cell = 1.0;
  int nx = 0, ny = 0;
  std::vector<double> z;  ///< nx * ny elevations, row j after row j - 1

  /// The terrain's elevation under (x, y), bilinear between cell centres, held flat past the edge.
  double elevation(double x, double y) const;
};

struct Ground {
  Terrain terrain;
  std::vector<std::uint8_t> is_ground;  ///< per point: 1 for ground
  std::vector<float> height;    ///< per point: height above the terrain
  std::size_t ground_points = 0;
};

/// Classifies the ground of `cloud`. When `classes` holds a class per point (LAS: 2 is ground) and
/// some are ground, those points are the ground and the terrain is made from them alone.
/// @throws InputError for an empty cloud.
Ground classify_ground(const PointCloud& cloud, const GroundOptions& options = {},
                       const std::vector<std::uint8_t>* classes = nullptr);

}  // namespace treeskel::forest
