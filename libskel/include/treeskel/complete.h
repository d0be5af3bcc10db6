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
/// result is still one tree, and every point still belongs to exactly one node. Two kinds of graft are
/// not branches and are not added: tufts that stay near the bark (noise) and bushes that fork into
/// many components in every band (leaves and needles).
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
  /// A graft whose farthest point lies no farther than this outside the tubes is a tuft on the bark
  /// (scanner noise, or the bark of a branch fitted a little thin), not a branch: a twig there would
  /// take a share of the pipe model from the branches (on the noisy synthetic clouds the models then
  /// held an eighth less of the true skeleton). Its points stay where they were. 0 (default): the
  /// margin plus the link distance (three octree cells).
  double min_reach = 0.0;
  /// A graft whose level sets hold more than this many components per band on average is a bush:
  /// leaves, needles or noise around twigs, whose tubes would fill the crown and cross one another
  /// (the union of TreeLS's spruce ran out of budget and its mesh held half the skeleton). It is not
  /// added; its points stay with the nodes that held them. 0: no limit.
  double max_branching = 2.0;
  /// Grow the tufts and the bushes too: a graft of `min_points` or more points is added however near
  /// the bark it stays (`min_reach` unused) and however it branches, so that every group of uncovered
  /// points gets a twig, as AdTree's models do (`treeskel model --complete-all`, `all_grafts()`);
  /// unless the bushes hold more than `max_bush_share` of the cloud's points.
  bool tufts_and_bushes = false;
  /// With `tufts_and_bushes`: past this share of the cloud in bushes, the crown is leafy or needled, not
  /// a crown of missed twigs, and its bushes are left out as without it (`CompleteStats::leafy_bushes`).
  /// TreeLS's spruce holds 0.37 of its points in bushes: grown, their twigs crossed one another
  /// everywhere and the unions ran for more than ten minutes in exact arithmetic. AdTree's samples
  /// hold 0-0.09, TreeLS's pine 0.14.
  double max_bush_share = 0.2;
};

/// The options that grow a twig through every group of at least `min_points` uncovered points: the
/// tufts on the bark and the bushes too, up to `max_bush_share` (`tufts_and_bushes`).
CompleteOptions all_grafts();

/// What `complete_skeleton` did.
struct CompleteStats {
  std::size_t uncovered_points = 0;  ///< points farther from the axis than its radius + margin
  std::size_t grafted_points = 0;    ///< of those, the ones now held by grafted nodes
  std::size_t branches = 0;          ///< grafted branches (each hangs from one existing node)
  std::size_t nodes = 0;             ///< nodes added
  std::size_t bushy_grafts = 0;      ///< grafts not added because they branch like a bush
  std::size_t bushy_points = 0;      ///< the uncovered points of those grafts
  /// With `tufts_and_bushes`: the bushes held more than `max_bush_share` of the cloud and were left out.
  bool leafy_bushes = false;
};

/// Grows branches through the points the skeleton leaves uncovered (see the file comment). Node ids of
/// the skeleton are kept; new nodes follow them. Deterministic, and independent of the thread count.
/// @param cell_size the octree cell size the skeleton was extracted with (scales the 0 defaults)
/// @pre `skeleton` is a tree whose node points index `cloud`.
CompleteStats complete_skeleton(Skeleton& skeleton, const PointCloud& cloud, double cell_size,
                                const CompleteOptions& options = {});

}  // namespace treeskel
