/// @file junction.h
/// Fork placement. Level sets put a fork where the band first splits, which is where the surfaces of
/// the child branches part: about r / sin(half the branching angle) above the point where the branch
/// axes meet, and the paper's refinement moves it by at most one band. This stage (not in the paper)
/// moves every branch node to the point nearest, in the least-squares sense, to the axis lines of its
/// arms, each fitted to the arm's nodes a little away from the junction; nodes the move leaves on the
/// wrong side of the fork are merged into it, so their points stay owned.
#pragma once

#include "treeskel/skeleton.h"

namespace treeskel {

struct JunctionOptions {
  /// Length of each arm used to fit its axis. 0 (default): 5 band widths or 3 radii of the branch
  /// below the fork, whichever is longer.
  double arm_length = 0.0;
  /// Arm part next to the fork left out of the fit (the junction bends it). 0 (default): 1 band width
  /// or 1 radius of the branch below the fork, whichever is longer.
  double skip = 0.0;
  /// Largest move, in radii of the branch below the fork (plus one band width).
  double max_move_radii = 2.5;
  /// Pull toward the current position (regularises nearly parallel arms); relative to one arm's weight.
  double stay_weight = 0.05;
};

/// Relocates the branch nodes. Returns the number of nodes moved.
/// @param[in] band_width  the level sets' band width, which scales the defaults
std::size_t relocate_forks(Skeleton& skeleton, double band_width, const JunctionOptions& options = {});

}  // namespace treeskel
