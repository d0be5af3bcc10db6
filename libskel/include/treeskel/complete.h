/// @file complete.h
/// Completion of the skeleton for a model that shows the whole scan. Where a crown is crowded or
/// sparsely sampled, one band component of the level sets can hold the points of several twigs; its
/// node sits between them, and pruning takes twigs a few cells long. Those points then lie far
/// outside the branch their node stands for, and a mesh swept along the skeleton misses them.
///
/// This stage finds the points farther from the skeleton's axis than the radius there plus a margin,
/// and grows new branches through them: a shortest-path forest over those points, rooted where they
/// touch the points the skeleton already covers, cut into level sets of its path length as the main
/// skeleton is. Each grafted branch hangs from the skeleton node nearest to where it starts, so the
/// result is still one tree, and every point still belongs to exactly one node.
#pragma once

#include "treeskel/point_cloud.h"
#include "treeskel/skeleton.h"

#include <cstddef>

namespace treeskel {

struct CompleteOptions {
  /// A point is uncovered when its distance to the skeleton's axis exceeds the radius there plus this
  /// margin. 0 (default): one octree cell.
  double margin = 0.0;
  /// Uncovered points closer than this are neighbours, and one this close to a covered point starts a
  /// path. 0 (default): two octree cells.
  double link = 0.0;
  /// Width of a level set of path length along the grafted forest. 0 (default), or anything narrower
  /// than `link`: `link`.
  double band_width = 0.0;
  /// A grafted branch (all that hangs from one skeleton node) with fewer points is not added; its
  /// points stay with the nodes that held them.
  std::size_t min_points = 4;
};

/// What `complete_skeleton` did.
struct CompleteStats {
  std::size_t uncovered_points = 0;  ///< points farther from the axis than its radius + margin
  std::size_t grafted_points = 0;    ///< of those, the ones now held by grafted nodes
  std::size_t branches = 0;          ///< grafted branches (each hangs from one existing node)
  std::size_t nodes = 0;             ///< nodes added
};

/// Grows branches through the points the skeleton leaves uncovered (see the file comment). Node ids of
/// the skeleton are kept; new nodes follow them. Deterministic, and independent of the thread count.
/// @param cell_size the octree cell size the skeleton was extracted with (scales the 0 defaults)
/// @pre `skeleton` is a tree whose node points index `cloud`.
CompleteStats complete_skeleton(Skeleton& skeleton, const PointCloud& cloud, double cell_size,
                                const CompleteOptions& options = {});

}  // namespace treeskel
