/// @file plots.h
/// Synthetic plot scans with the truth per point, and the scores of a segmentation against it:
/// several of the generator's trees with overlapping crowns on a rough, sloping ground, shrubs of
/// understorey, leaves as small clusters at the twigs' tips, each tree seen from a few scanner
/// positions (the side of each branch facing a scanner). Deterministic for a seed.
#pragma once

#include "treeskel/point_cloud.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace treeskel::eval {

struct PlotOptions {
  std::uint64_t seed = 1;
  int trees = 8;
  double width = 16.0;          ///< the plot is width x width, metres
  double min_spacing = 2.5;     ///< between stems
  double slope = 0.08;          ///< of the ground, rise over run
  double roughness = 0.08;      ///< amplitude of the ground's bumps
  int shrubs = 12;              ///< understorey
  bool leaves = true;
  int scanners = 3;             ///< positions around the plot
  std::size_t points_per_tree = 30000;  ///< wood points; leaves add about a half again
  double ground_density = 30.0;  ///< ground points per square metre
  double noise = 0.004;          ///< standard deviation along the surface normal
};

/// What a point of a synthetic plot is.
enum class PointKind : std::uint8_t { ground = 0, wood = 1, leaf = 2, understorey = 3 };

struct SyntheticPlot {
  PointCloud cloud;
  std::vector<std::uint32_t> tree;  ///< per point: 1 + the tree's index; 0 for ground and understorey
  std::vector<PointKind> kind;      ///< per point
  std::vector<Eigen::Vector3d> stems;  ///< each tree's base, local frame
};

SyntheticPlot make_plot(const PlotOptions& options = {});

/// A segmentation scored against the truth.
struct PlotScore {
  std::size_t true_stems = 0, found_stems = 0, matched_stems = 0;
  double stem_precision = 0.0, stem_recall = 0.0;
  /// Mean over the true trees of the IoU of its points with those of the found tree matched to it
  /// (0 for a tree whose stem was not found).
  double mean_iou = 0.0;
  /// Of the true trees' points: the share given to another found tree, and to none.
  double tree_points_elsewhere = 0.0, tree_points_unassigned = 0.0;
  /// Of the ground's and the understorey's points: the share given to a tree.
  double others_in_trees = 0.0;
};

/// Matches the found stems (plan positions) to the true ones within `match_distance` in plan, nearest
/// pairs first, each at most once, and scores the points' tree labels (`labels`: 1 + the index of the
/// found stem, 0 for none).
PlotScore score_plot(const SyntheticPlot& plot, const std::vector<Eigen::Vector2d>& found_stems,
                     const std::vector<std::uint32_t>& labels, double match_distance = 0.5);

}  // namespace treeskel::eval
