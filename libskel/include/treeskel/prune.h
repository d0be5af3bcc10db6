/// @file prune.h
/// Removal of spurious twigs. Where a branch surface is sparsely sampled, or near a tip, or in a tuft
/// of noise, a band breaks into pieces that the level sets turn into short side branches lying on the
/// surface of the branch they leave. The paper sets no threshold for them; this stage removes a leaf
/// branch that is shorter than a minimum length or that never reaches farther from the branch it
/// leaves than that branch's radius (times a factor), and gives its points to the fork node, so no
/// point is lost.
#pragma once

#include "treeskel/point_cloud.h"
#include "treeskel/skeleton.h"

namespace treeskel {

struct PruneOptions {
  /// A leaf branch (from its fork to its tip) shorter than this is removed. 0 (default): `min_bands`
  /// band widths.
  double min_length = 0.0;
  /// The shortest leaf branch kept when `min_length` is 0, in band widths. Half a band (default) is
  /// what the radius rule below implies anyway (a leaf reaches no farther from its branch than its
  /// length): the reach decides. A whole band took twigs of sparse scans whose last band component
  /// alone stands apart from the branch they leave; with half, those scans' BPC / EPC rose by
  /// 0.013-0.023 and their precisions fell by 0.002-0.009 (three seeds: 2,000-3,000 points 0.667 /
  /// 0.656 → 0.683 / 0.669, precision 0.755 / 0.821 → 0.747 / 0.812; 4,000-6,200 points 0.833 / 0.805
  /// → 0.856 / 0.824, 0.773 / 0.860 → 0.771 / 0.856), and the 72 clouds and the crowded crowns moved
  /// by at most 0.003 (docs/accuracy.md; `bench_accuracy --prune-bands 1` for the whole band). A
  /// model keeps a whole band (`modeling::use_model_pruning`).
  double min_bands = 0.5;
  /// ... or one whose nodes all stay within this many radii (plus half a band) of the branch it
  /// leaves: the axis through a few nodes below the fork and along its other children, whose median
  /// radius is the host radius.
  double radius_factor = 1.75;
  int host_nodes = 4;  ///< nodes of each neighbouring chain that define the host branch
  /// The radius rule with the points' help, when > 0 and the cloud is given (the pipeline gives it):
  /// the host radius is the smaller of the nodes' median radius and the median distance of the host
  /// nodes' points from the host axis (at most 256 of them, evenly strided), and a leaf whose nodes
  /// stay within this many of it (plus half a band) is spurious; `radius_factor` then serves only
  /// where the host nodes hold no point. The nodes' radii near a fork grow with the twig that leaves
  /// there: where the rule on them removed a true twig (seed 1's hard sets, a twig whose tip lies
  /// within 0.02 of a true tip), the host radius was a median 2.7-5 times the true parent's; where it
  /// removed a spur, 0.9-1.1 times. The points' spread grows with foliage around the host (a
  /// spruce's needles): the smaller of the two. Three seeds: the 72 clouds' branch-point precision
  /// +0.005-0.010 at BPC within 0.004, every degradation at once precision 0.823 → 0.851, the sparse
  /// scans' BPC up, the crowded crowns' BPC 0.571 → 0.543 (docs/accuracy.md, README "Spurs judged
  /// with their host's points"). 0: the node radii with `radius_factor` (a model's,
  /// `modeling::use_model_pruning`).
  double point_host_factor = 2.25;
  /// Forks this many bands or less apart along the skeleton are a close pair, and the level sets'
  /// making more often than the tree's: where one true fork's branches leave a band or two apart, a
  /// spur beside them made it two (on seed 1's sparse scans and every-degradation clouds, most of
  /// the predicted forks no true one matched lay within τ of a true fork another had matched, a
  /// median 0.016-0.021 along the skeleton from the next predicted fork; 90% of the true forks lie
  /// 0.046 or more from the next). At a close pair, a fork's shortest leaf arm no longer than `close_fork_leaf` bands
  /// goes, its points to the fork (`prune_spurs_at_close_forks`, after fork placement). 0: off (a
  /// model's, `modeling::use_model_pruning`: the mesh keeps those twigs). Measured in
  /// docs/accuracy.md and the README ("Spurs at close forks").
  double close_forks = 1.5;
  double close_fork_leaf = 3.0;  ///< the longest leaf arm removed at a close pair, in bands
};

/// The shortest leaf branch `options` keep: `min_length`, or `min_bands` times `band_width` when it is 0.
double prune_length_for(const PruneOptions& options, double band_width);

/// Removes spurious leaf branches until none is left; where every child of a fork is short, the longest
/// stays (it is the continuation of the branch). Returns the number of branches removed.
/// @param[in] band_width  the level sets' band width, which scales the default `min_length`
std::size_t prune_short_branches(Skeleton& skeleton, double band_width, const PruneOptions& options = {},
                                 const PointCloud* cloud = nullptr);

/// At every fork within `options.close_forks` bands of another (see PruneOptions), in node order,
/// removes its shortest leaf arm if it is at most `close_fork_leaf` bands long; the arm's points go to
/// the fork. Returns the number of arms removed.
std::size_t prune_spurs_at_close_forks(Skeleton& skeleton, double band_width, const PruneOptions& options = {});

}  // namespace treeskel
