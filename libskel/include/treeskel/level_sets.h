/// @file level_sets.h
/// The initial skeleton from level sets of the geodesic distance (Fu et al. 2020, section IV.B, after
/// Verroust and Lazarus 2000). Each band of geodesic distance is split into the branches that cross it;
/// the paper uses spectral clustering on the band, we use the connected components of the neighbour
/// graph restricted to the band, which separates the same branches in linear time.
#pragma once

#include "treeskel/geodesic.h"
#include "treeskel/l1_median.h"
#include "treeskel/neighbour_graph.h"
#include "treeskel/octree.h"
#include "treeskel/point_cloud.h"
#include "treeskel/skeleton.h"

#include <vector>

namespace treeskel {

struct LevelSetOptions {
  /// Width ρ of a band of geodesic distance. 0 (default): 2 cell sizes, the narrowest band whose
  /// cross-section of a branch surface stays connected in the octree's neighbour graph.
  double band_width = 0.0;
  L1MedianOptions median;  ///< for the node positions
  /// Components of one band that hang from the same node and come closer to each other than this
  /// share of that node's radius are one ring broken by sparse sampling, and make one node; a real
  /// fork's branches part by more a band or two higher. 0: never join.
  double join_factor = 0.5;
};

/// One node per (band, branch): at the L1-median of the points of its cells, with the radius of eq. 9
/// (mean distance of those points to the node). Each node hangs from the node that holds the
/// shortest-path predecessor of its lowest cell, so the result is a tree rooted at the band of the
/// root cells; close siblings are joined (see `join_factor`). Points of cells outside `in_tree` or not
/// reached become noise.
Skeleton level_set_skeleton(const PointCloud& cloud, const OctreeCells& cells, const CellGraph& graph,
                            const std::vector<bool>& in_tree, const GeodesicField& geodesic,
                            const LevelSetOptions& options = {});

/// The band width `options` give for these cells: `band_width`, or 2 cell sizes when it is 0.
double band_width_for(const LevelSetOptions& options, const OctreeCells& cells);

/// Mean distance from the points to `centre` (eq. 9); 0 for no points.
double mean_distance(const std::vector<Eigen::Vector3d>& positions, const std::vector<std::uint32_t>& points,
                     const Eigen::Vector3d& centre);

}  // namespace treeskel
