/// @file pipeline.h
/// `extract_skeleton`: the whole method of Fu, Liu, Zhou, Zhang and Lin, "Tree Skeletonization for Raw
/// Point Cloud Exploiting Cylindrical Shape Prior", IEEE Access 8 (2020), composed from its stages:
/// octree L1-medians → neighbour graph (+ gap bridging) → geodesic distance → level sets → pruning of
/// spurious twigs → CPC recentring → topology refinement → fork placement → cardinal-spline smoothing.
#pragma once

#include "treeskel/cpc.h"
#include "treeskel/geodesic.h"
#include "treeskel/junction.h"
#include "treeskel/level_sets.h"
#include "treeskel/neighbour_graph.h"
#include "treeskel/octree.h"
#include "treeskel/point_cloud.h"
#include "treeskel/prune.h"
#include "treeskel/refine.h"
#include "treeskel/skeleton.h"
#include "treeskel/smooth.h"

#include <functional>
#include <string>
#include <vector>

namespace treeskel {

/// Called between stages with the stage about to run and the share of the work done (0 to 1).
using ProgressFn = std::function<void(const std::string& stage, double done)>;

/// Every option of the method. Distances are in the cloud's units; 0 means "relative to the octree's
/// cell size" as each stage documents, so the defaults follow the cloud's scale.
struct SkeletonOptions {
  OctreeOptions octree;
  NeighbourGraphOptions graph;
  RootOptions root;
  LevelSetOptions level_sets;
  PruneOptions prune;
  CpcOptions cpc;
  RefineOptions refine;  ///< its `cpc` is replaced by `cpc` above
  JunctionOptions junctions;
  SmoothOptions smooth;
  bool use_prune = true;
  bool use_cpc = true;
  bool use_refine = true;
  bool use_junctions = true;
  bool use_smooth = true;
  std::size_t min_points = 10;  ///< fewer points than this is an error
  ProgressFn progress;          ///< optional
};

/// What the run did, for reports.
struct SkeletonStats {
  std::size_t points = 0;
  int octree_depth = 0;
  double cell_size = 0.0;
  double band_width = 0.0;
  std::size_t cells = 0;
  std::size_t graph_edges = 0;
  std::size_t bridges = 0;          ///< edges added to bridge occlusion gaps
  std::size_t parts = 0;            ///< connected parts of the graph after bridging
  std::size_t level_set_nodes = 0;  ///< nodes of the initial skeleton
  std::size_t pruned_branches = 0;
  std::size_t refined_splits = 0;
  std::size_t forks_moved = 0;
  std::vector<std::pair<std::string, double>> seconds;  ///< wall time per stage
};

/// `options` with every scale that defaults to a multiple of the octree cell (0) replaced by the value
/// `extract_skeleton` would use on `cloud`: the octree depth, the band width, the pruning length, the
/// bridging distance and the root slice. Extracting with the result gives the same skeleton; front
/// ends show these numbers as the defaults in the cloud's units.
/// @throws InputError as `extract_skeleton` does for a cloud it cannot use.
SkeletonOptions automatic_options(const PointCloud& cloud, const SkeletonOptions& options = {});

/// Extracts the curve skeleton of a tree.
/// @throws InputError when the cloud is empty, too small, all at one place, on one line, or yields no
///         skeleton; OptionError for an option out of range.
Skeleton extract_skeleton(const PointCloud& cloud, const SkeletonOptions& options = {}, SkeletonStats* stats = nullptr);

}  // namespace treeskel
