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

/// The ground a single tree's scan stands on, when it holds some (terrestrial scans of one tree often
/// keep a disc of ground around the stem).
struct GroundUnderTree {
  std::vector<std::uint8_t> is_ground;  ///< per point: 1 for ground; empty when the scan holds none
  std::size_t ground_points = 0;  ///< points set aside: the ground and what lies on it
  std::size_t beyond_stem = 0;  ///< of the ground points found, those farther out than the stem's foot
  double stem_radius = 0.0;     ///< the stem's radius in the slice above the ground (0: no stem seen)
};

/// The ground under one tree: classify_ground on the cloud turned so that `up` is its z, kept only
/// when the stem stands on it: find_stems sees a stem above it (the thickest is taken) and at least
/// `kGroundBeyondStem` of its points (and a thousandth of the cloud) lie farther out in plan than
/// three stem radii and 0.3 m beyond the stem. Set aside are then the ground outside the stem (its
/// radius + 10%, at least 2 cm: the stem's own foot stays, so the tree keeps its height) and what
/// lies on the ground below the stems' slice (0.3 m; litter, low plants, the ground's noise) more
/// than 1.5 stem radii (+ 5 cm) from the stem.
/// A tree scanned without ground has, as its "ground", the lowest points of its stem, which lie
/// within that circle: nothing is then set aside. Distances in metres, as plots'; a cloud taller
/// than 200 units (not metres) or under 1 unit is left as it is.
GroundUnderTree ground_under_tree(const PointCloud& cloud, const Eigen::Vector3d& up);

/// Ground points beyond the stem that make a scan's ground (see ground_under_tree).
constexpr std::size_t kGroundBeyondStem = 50;

}  // namespace treeskel::forest
