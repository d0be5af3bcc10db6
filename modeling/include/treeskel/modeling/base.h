/// @file base.h
/// The trunk down to its points: the skeleton's root is the median of the lowest level set's points,
/// half a band or so above where the scan of the trunk ends, and a model swept from it starts that
/// far above the ground.
#pragma once

#include "treeskel/point_cloud.h"
#include "treeskel/skeleton.h"

namespace treeskel::modeling {

/// Moves the root of `skeleton` down its trunk's axis (from the node at least two root radii up the
/// thickest path, through the root) to where the root's own points end: by the 95th percentile of
/// their distances below the root along that axis, at most four root radii. Nothing moves when the
/// root holds fewer than three points, has no child, or its points end above it. Returns the distance
/// the root moved (0 when it did not).
double reach_down(Skeleton& skeleton, const PointCloud& cloud);

}  // namespace treeskel::modeling
