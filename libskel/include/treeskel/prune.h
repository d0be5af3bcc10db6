/// @file prune.h
/// Removal of spurious twigs. Where a branch surface is sparsely sampled, or near a tip, or in a tuft
/// of noise, a band breaks into pieces that the level sets turn into short side branches lying on the
/// surface of the branch they leave. The paper sets no threshold for them; this stage removes a leaf
/// branch that is shorter than a minimum length or that never reaches farther from the branch it
/// leaves than that branch's radius (times a factor), and gives its points to the fork node, so no
/// point is lost.
#pragma once

#include "treeskel/skeleton.h"

namespace treeskel {

struct PruneOptions {
  /// A leaf branch (from its fork to its tip) shorter than this is removed. 0 (default): 1 band width.
  double min_length = 0.0;
  /// ... or one whose nodes all stay within this many radii (plus half a band) of the branch it
  /// leaves: the axis through a few nodes below the fork and along its other children, whose median
  /// radius is the host radius.
  double radius_factor = 1.75;
  int host_nodes = 4;  ///< nodes of each neighbouring chain that define the host branch
};

/// The shortest leaf branch `options` keep: `min_length`, or `band_width` when it is 0.
double prune_length_for(const PruneOptions& options, double band_width);

/// Removes spurious leaf branches until none is left; where every child of a fork is short, the longest
/// stays (it is the continuation of the branch). Returns the number of branches removed.
/// @param[in] band_width  the level sets' band width, which scales the default `min_length`
std::size_t prune_short_branches(Skeleton& skeleton, double band_width, const PruneOptions& options = {});

}  // namespace treeskel
