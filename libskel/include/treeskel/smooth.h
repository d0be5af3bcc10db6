/// @file smooth.h
/// Cardinal-spline smoothing of the skeleton (Fu et al. 2020, end of section IV.D): a number of points
/// (five in the paper) is interpolated between every two adjacent nodes.
#pragma once

#include "treeskel/skeleton.h"

namespace treeskel {

struct SmoothOptions {
  int samples_per_edge = 5;  ///< nodes inserted between two adjacent nodes
  double tension = 0.0;      ///< cardinal spline tension c in [0, 1]; 0 is Catmull-Rom, 1 straight lines
};

/// Returns a skeleton whose first nodes are the input's (same ids, positions, radii and points),
/// followed by the interpolated nodes, which carry no points and linearly interpolated radii. On each
/// edge parent→child the tangents come from the parent's parent and, where the child continues in a
/// single branch, the child's child; at the root, tips and forks the missing neighbour is mirrored.
Skeleton smooth_skeleton(const Skeleton& skeleton, const SmoothOptions& options = {});
/// The same, taking the input's point lists instead of copying them.
Skeleton smooth_skeleton(Skeleton&& skeleton, const SmoothOptions& options = {});

}  // namespace treeskel
