/// @file prune.h
/// Removal of spurious twigs. A band that cuts a branch surface near a tip, or a tuft of noise, breaks
/// into small pieces that the level sets turn into short side branches. The paper sets no threshold
/// for them; this stage removes leaf branches shorter than a length relative to the branch they leave
/// and gives their points to the fork node, so no point is lost.
#pragma once

#include "treeskel/skeleton.h"

namespace treeskel {

struct PruneOptions {
  /// A leaf branch (from its fork to its tip) shorter than this is removed. 0 (default): 2 band widths.
  double min_length = 0.0;
  /// ... or shorter than this many times the radius of the fork node it leaves.
  double radius_factor = 1.5;
};

/// Removes short leaf branches until none is left; where every child of a fork is short, the longest
/// stays (it is the continuation of the branch). Returns the number of branches removed.
/// @param[in] band_width  the level sets' band width, which scales the default `min_length`
std::size_t prune_short_branches(Skeleton& skeleton, double band_width, const PruneOptions& options = {});

}  // namespace treeskel
