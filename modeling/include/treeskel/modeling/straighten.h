/// @file straighten.h
/// Limbs as stiff as their thickness: the skeleton's path along each limb smoothed over a length
/// that grows with the limb's radius, so that a trunk does not zigzag where a sparse scan's level
/// sets wandered from twig to twig, while a twig keeps every bend its points show.
#pragma once

#include "treeskel/skeleton.h"

#include <cstddef>

namespace treeskel::modeling {

/// What `straighten_limbs` did.
struct StraightenStats {
  std::size_t limbs = 0;        ///< limbs smoothed (paths that follow the thickest child at every fork)
  std::size_t moved = 0;        ///< nodes moved by more than a hundredth of their radius
  double largest_shift = 0.0;   ///< the largest move of a node, in the skeleton's units
  /// The largest move the smoothing of a node's own limb gave it, in its radii (a side twig that
  /// follows its fork moves farther, by the fork's move, which says nothing about its own radius).
  double largest_shift_radii = 0.0;
};

/// Smooths the path of every limb of `skeleton` (which has its radii): from the root, or from the
/// fork it leaves, a limb follows the child whose first node is thickest at every fork to a tip. Each
/// node moves to the Gaussian-weighted mean of its limb's nodes, weighted by the distance along the
/// limb with a spread of `factor` times the node's own radius (nodes farther than three spreads
/// weigh nothing). Held where they are: the root, the forks where two limbs part (the second child at
/// least half as thick as the first) and the tips of the limbs; each run between them is mirrored
/// through its two ends (an odd reflection), so that a straight limb stays straight. A fork with
/// thinner side limbs moves with its limb, and its side limbs follow it, each node by the fork's move
/// weighted as above by its distance from the fork over the fork's spread (a short twig moves whole,
/// its tip too) before the side limb is smoothed in turn. Radii, edges and each node's points are
/// kept. A spread is a length along the limb: a bend much longer than the limb's radius stays (a limb
/// of radius r that bends with a curvature radius R moves by about (factor r)^2 / 2R). `factor` 0
/// changes nothing.
/// @throws OptionError for a negative or non-finite `factor`.
/// @throws InputError when the skeleton is empty or not a tree.
StraightenStats straighten_limbs(Skeleton& skeleton, double factor);

}  // namespace treeskel::modeling
