/// @file hard_trees.h
/// Harder ground-truth sets than the paper's, of the kinds real scans are full of:
///   crowded crowns  the complex trees' topologies (trees 4-6) grown with short, steep side branches
///                   that are hardly steered apart, so forks lie closer than a level-set band and twigs
///                   of neighbouring limbs interleave;
///   sparse scans    large trees (60-230 branch points) seen by a virtual scanner from one to three
///                   places with 2,000-6,200 points, so the far side and thin tips get few or none; the
///                   truth is cut back to what the scan shows (`cut_to_scan`);
///   every degradation at once  the paper's six trees seen from one side, with holes, noise, outliers
///                   and a varying density together.
/// Deterministic for a seed, normalised like the paper's trees (longest side 1), scored with τ = 0.05.
#pragma once

#include "treeskel/eval/paper_trees.h"

#include <cstdint>
#include <string>
#include <vector>

namespace treeskel::eval {

/// One cloud of a harder set with the truth it is scored against.
struct HardCloud {
  std::string name;  ///< e.g. "crowded5_23011", "sparse130_2views_2688", "tree4_all"
  std::string group;  ///< the table row it is averaged in, e.g. "sparse scans, 2,000-3,000 points"
  GroundTruth truth;
  PointCloud cloud;
};

/// The crowded-crown shape: the paper's counts for trees 4-6, side branches at 15-35 degrees and
/// 0.55-0.72 of their parent's length, placed with little search for room (10 tries, content with a
/// clearance of 15% of their length).
TreeShape crowded_shape(int index);

/// Tree 4, 5 or 6's counts grown with `crowded_shape`.
GroundTruth make_crowded_tree(int index, std::uint64_t seed = 1);

/// The nine crowded clouds: trees 4-6 at the paper's three point counts each.
std::vector<HardCloud> make_crowded_clouds(std::uint64_t seed = 1);

struct ScanOptions {
  std::size_t points = 3000;  ///< in all, shared evenly by the scanners
  int scanners = 1;           ///< placed evenly around the tree (with some disorder), one to three
  double distance = 1.2;      ///< horizontal distance from the tree's axis, in units of the tree's size
  double height = 0.2;        ///< scanner height above the trunk base, same units
  double noise = 0.0005;      ///< range noise, same units
  std::uint64_t seed = 1;
};

/// Points a terrestrial scanner records of the wood from `options.scanners` places (see
/// `SurfaceSampling::viewpoint` for what one scanner sees).
PointCloud virtual_scan(const GroundTruth& truth, const ScanOptions& options);

struct CutOptions {
  double reach = 0.02;   ///< beyond the node's radius, in units of the tree's size (two node spacings)
  int min_points = 2;    ///< points within reach that make an endpoint seen
  /// Count only the branch's own points: those whose nearest piece of wood (the tube of a truth edge,
  /// by the distance to its surface) is one of the edges within `reach` of the endpoint along its own
  /// branch. Counted whoever's they were, a twig in a crowded crown was "seen" by the points of its
  /// neighbours: on the sparse scans of 2,000-3,000 points, 60% of the true twigs kept had fewer than
  /// three points of their own, and the set scored a method on forks no scan could show.
  bool own_points = true;
};

/// The part of `truth` that `cloud` shows (compared in the world frame, position + offset): endpoints
/// (other than the root) with fewer than `min_points` points within their radius + `reach` (the
/// branch's own, see `CutOptions::own_points`) are removed, again and again, so every branch is cut
/// back to its last seen node. Branch points whose branches were cut away become plain nodes; the
/// root and every node on the way to a seen tip stay, gaps of an occlusion included. The cylinders stay.
GroundTruth cut_to_scan(const GroundTruth& truth, const PointCloud& cloud, const CutOptions& options = {});

/// The eighteen sparse clouds: trees of 60, 130 and 230 branch points, each scanned from one, two and
/// three places, with 2,000-3,000 points and again with 4,000-6,200, the truth cut back to each scan.
/// `cut`: the rule the truth is cut back with (the default counts each branch's own points).
std::vector<HardCloud> make_sparse_clouds(std::uint64_t seed = 1, const CutOptions& cut = {});

/// The six clouds with every degradation at once, one per paper tree ("tree1_all" ... "tree6_all"):
/// seen from one side, four holes, Gaussian noise of 0.003, 1% outliers, density waves; the paper's
/// first point count.
std::vector<HardCloud> make_combined_clouds(std::uint64_t seed = 1);

/// The three harder sets in this order: crowded crowns, sparse scans, every degradation at once.
std::vector<HardCloud> make_hard_clouds(std::uint64_t seed = 1, const CutOptions& cut = {});

}  // namespace treeskel::eval
