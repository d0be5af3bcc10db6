/// @file base.h
/// The trunk down to its points: the skeleton's root is the median of the lowest level set's points,
/// half a band or so above where the scan of the trunk ends, and a model swept from it starts that
/// far above the ground.
#pragma once

#include "treeskel/point_cloud.h"
#include "treeskel/skeleton.h"

namespace treeskel::modeling {

/// Moves the root of `skeleton` onto its trunk's axis, where the root's own points end along it.
/// The axis is the principal direction of the nodes of the thickest path up to six root radii from
/// the root (the root left out); the root goes to the 95th percentile of its points' distances down
/// that axis, or to its own level on the axis if that is lower, but not below the lowest of them
/// along the way from the skeleton's centre to its root. Only the points within two root radii of
/// the axis count (the trunk's bark; not the ground or roots around it). A root the level sets put
/// beside the axis (the median of a flared base) goes onto it. Nothing moves when fewer than three
/// points count, the path has fewer than three nodes, the axis points down more than 45 degrees
/// away from the way from the skeleton's centre to its root (a base that wanders sideways through
/// roots or ground), or the move would be longer than four root radii (the axis or the points are
/// not a trunk's base). Returns the distance the root moved (0 when it did not).
double reach_down(Skeleton& skeleton, const PointCloud& cloud);

}  // namespace treeskel::modeling
