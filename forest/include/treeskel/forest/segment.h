/// @file segment.h
/// Every point of a plot to one tree: the points off the ground in voxels, the voxels joined to their
/// 26 neighbours, and each voxel given to the stem it is nearest to along that graph (multi-source
/// Dijkstra from the stems' voxels, as in TreeIso and 3DFin), so that touching crowns part where the
/// paths from the two stems meet. Parts the graph does not join to any stem (a twig cut off by
/// occlusion, understorey) go to the tree of the nearest assigned voxel when it is near enough and
/// they rise above the understorey; otherwise they belong to no tree.
#pragma once

#include "treeskel/forest/ground.h"
#include "treeskel/forest/stems.h"
#include "treeskel/point_cloud.h"

#include <cstdint>
#include <vector>

namespace treeskel::forest {

struct SegmentOptions {
  double voxel = 0.07;        ///< voxel edge (0.07 scored a mean IoU of 0.86 on the synthetic plots, 0.1 0.84, 0.05 0.85)
  double seed_margin = 0.1;   ///< a stem's seeds: its voxels below the slice's top within radius + this
  double max_gap = 1.0;       ///< a part apart from every tree joins the nearest one up to this far
  double understorey = 1.5;   ///< ... unless it stays below this height above the ground
};

struct Segmentation {
  /// Per point: 1 + the index of its stem; 0 for none (the ground, understorey). The ground's points
  /// inside a stem's circle (radius + seed margin) are that tree's: its base.
  std::vector<std::uint32_t> tree;
  std::size_t voxels = 0;
  std::size_t unreached_voxels = 0;  ///< voxels left in no tree
  std::size_t unassigned_points = 0;  ///< points off the ground in no tree
  std::size_t stem_base_points = 0;   ///< ground points given to a tree as its base
};

/// Assigns the points that are not ground to the trees of `stems`.
Segmentation segment_trees(const PointCloud& cloud, const Ground& ground, const std::vector<Stem>& stems,
                           const StemOptions& stem_options = {}, const SegmentOptions& options = {});

/// What a tree's points say about it.
struct TreeShape {
  std::size_t points = 0;
  double height = 0.0;      ///< of its highest point above the ground under its stem
  double crown_base = 0.0;  ///< height of the lowest layer whose points spread away from the stem
  Eigen::Vector3d low = Eigen::Vector3d::Zero(), high = Eigen::Vector3d::Zero();  ///< its bounding box
};

/// The shape of every tree (index = stem index). The crown base is the bottom of the lowest 0.25 m
/// layer above the stem slice's bottom in which a tenth of the layer's points (at least 10) lie farther than
/// max(1, 4 stem radii) from the stem in plan; the tree's height when no layer does.
std::vector<TreeShape> describe_trees(const PointCloud& cloud, const std::vector<Stem>& stems,
                                      const Segmentation& segmentation, const StemOptions& stem_options = {});

}  // namespace treeskel::forest
