/// @file sweep.h
/// One watertight mesh of a tree: generalized cylinders swept along the skeleton's branches, joined
/// at forks by the convex hull of the rings that meet there, the base and the tips capped.
#pragma once

#include "treeskel/modeling/tree_mesh.h"
#include "treeskel/skeleton.h"

#include <cstddef>

namespace treeskel::modeling {

struct SweepOptions {
  int trunk_segments = 24;  ///< polygon sides around the thickest branch; thinner ones get fewer
  int min_segments = 6;     ///< fewest polygon sides around a branch
  int max_segments = 48;    ///< most polygon sides around a branch
  /// Branches whose radius where they start is below this are left out with everything they carry
  /// (input units; 0, the default, keeps every branch): the only size limit of the mesh.
  double min_radius = 0.0;
  /// Radii below this share of the thickest radius are raised to it in the mesh (the skeleton's
  /// radii, and so the measurements, keep their values). The pipe model can leave a twig a millionth
  /// of the trunk, whose rings would collapse to points in the 32-bit floats every mesh format
  /// stores; raised, the twig stays visible and the saved mesh manifold (0: no floor).
  double min_relative_radius = 1e-3;
  /// ... and below this share of the tree's extent (the largest side of its box): thinner tubes,
  /// once rounded to the 32-bit floats of mesh files, fold into themselves where they meet others.
  double min_extent_radius = 1e-4;
  /// Along a branch a new ring is laid when the branch has run this many radii since the last one ...
  double ring_spacing = 0.75;
  /// ... or has turned by more than this (radians); but not where the tube may run straight past it
  /// to the next point (the skeleton in between within half its radius of the straight axis, the
  /// radius within 3% of the straight taper, the band under 2% of the tree's extent).
  double max_turn = 0.3;
  /// A branch leaving a thicker one at less than this angle (radians) is re-attached where it comes
  /// out of the thicker one's surface, so that the join stays compact (0: never).
  double narrow_angle = 0.7;
  /// The rings of a fork's join lie within this many radii (of its thickest branch) of the fork.
  /// Branches meeting at a narrow angle need more room: they are thinned where they meet (a neck)
  /// until their rings fit; a twig shorter than the room is left inside the join.
  double join_reach = 4.0;
  /// A twig whose ring does not fit at its fork is left inside the join when it is no longer than
  /// this many radii of the thickest branch there (it then ends inside that branch's wood); a longer
  /// one is swept apart and united with the tree. So is the branch that keeps the base's ring from
  /// fitting when the base is farther than `join_reach` from the fork.
  double absorb_length = 1.0;
  /// Most thinning steps (x0.8 each) at a narrow fork before its neighbouring fork is merged in.
  int max_necks = 10;
  /// Rounds of repair: branches whose surface meets another's are thinned, then left out.
  int repair_rounds = 12;
  /// Factor applied to the radii of a branch (and what it carries) in each repair round.
  double repair_shrink = 0.7;
  /// A branch thinned this many times is left out instead.
  int max_shrinks = 3;
  /// Only branches thinner than this share of the thickest radius may be left out by the repair;
  /// thicker ones are thinned further instead.
  double max_drop_radius = 0.25;
  /// A branch that carries at least this share of the tree's wood (the frustums of it and all it
  /// carries) is swept apart at its first crossing, at its own radii, and united with the tree,
  /// rather than thinned with all it carries. 1 or more: thinned as any branch.
  double max_thinned_share = 0.02;
  /// Where limbs swept apart are united with the tree, edges shorter than this share of the tree's
  /// extent are collapsed: 32-bit floats (every mesh format but OBJ) hold about 1.2e-7 of it, so
  /// vertices closer than a few of those would merge in the file.
  double weld = 1e-6;
  /// Sweep apart and unite the branches a join or a crossing leaves no room for (costly: seconds to
  /// tens of seconds on crowded crowns). Without it they are left out, and the coverage says how much.
  bool unite_apart = true;
  /// Run the self-intersection test and the repair (costly on large trees).
  bool repair = true;
  /// The file will hold the skeleton's local frame in 32-bit floats (glTF always; every format with
  /// `model --local`): the union rounds its points to those floats and the crossings are tested in
  /// them. Otherwise in the floats of the input's frame (of the local one for a georeferenced tree,
  /// whose floats would round the input's frame): a mesh checked in one frame's floats can cross
  /// itself once written in the other's (AdTree's tree13 with --complete: 6 face pairs in its --local PLY).
  bool local_floats = false;
};

/// What `sweep_mesh` did, for reports.
struct SweepStats {
  /// Chains swept into tubes. A piece split for the union counts what its parts' sweeps count, not
  /// its own as well; a chain a split cuts into two overlapping halves counts once per half.
  std::size_t branches = 0;
  std::size_t junctions = 0;         ///< convex-hull joins (a join may hold several close forks)
  std::size_t merged_forks = 0;      ///< forks joined with a neighbour into one hull
  std::size_t straightened_branches = 0;  ///< branches between two forks that doubled back, swept straight
  std::size_t thin_left_out = 0;     ///< branches under `min_radius`, left out
  std::size_t raised_to_floor = 0;   ///< nodes whose radius was raised to `min_relative_radius`
  std::size_t relocated_branches = 0;  ///< narrow-angle branches re-attached where they emerge
  std::size_t twigs_absorbed = 0;    ///< twigs too short to leave their fork's hull, left out
  std::size_t joins_thinned = 0;     ///< times the root's chain was thinned so that the joins at both its ends fit
  std::size_t joins_dropped = 0;     ///< branches swept apart (at their radii) where their joins did not fit
  std::size_t repaired_shrunk = 0;   ///< branches thinned to clear an intersection
  std::size_t repaired_dropped = 0;  ///< branches swept apart to clear an intersection
  int repair_rounds = 0;
  /// Repair rounds started by CGAL's test of the whole mesh: crossings the faster test of the parts
  /// that share no ring did not see. A band that folds over itself where a branch kinks is one
  /// (AdTree's tree7 has five such rounds); the bundled clouds and the synthetic trees have none.
  int late_repair_rounds = 0;
  int attempts = 0;                  ///< times the mesh was built (each repair round builds it again)
  std::size_t self_intersections = 0;  ///< face pairs still intersecting after the repair
  /// Subtrees that a join or a crossing left no room for, swept on their own and united with the
  /// tree (CGAL corefinement): `joins_dropped` and `repaired_dropped` count these, not losses.
  std::size_t pieces = 0;
  std::size_t unions = 0;          ///< corefinements run to unite the pieces (retries included)
  std::size_t pieces_apart = 0;    ///< pieces the union refused, kept as components of their own
  std::size_t pieces_nudged = 0;   ///< times a piece was moved by 1e-5 of the extent to clear a float crossing
  /// Pieces missing from the mesh: swept even alone only as a single failing segment, or left out
  /// because uniting them made the mesh cross itself (in the floats files hold) even split down to
  /// single segments, or past the union's budget (2000 pieces, 200 unions a tree; 8 pieces a group
  /// and 48 corefinements a union), or with `unite_apart` off.
  std::size_t pieces_failed = 0;
  std::size_t welded_edges = 0;    ///< edges shorter than `weld` collapsed after the union
  std::size_t voids_filled = 0;    ///< pockets of air the united pieces enclosed, filled (see mesh_union.h)
  /// Face pairs that cross once the mesh is rounded to the 32-bit floats of the frame files hold
  /// (tested where pieces were united; the union adds none to what the tree had without them).
  std::size_t float_crossings = 0;
  /// Wall time of the mesh's stages, the whole tree's only (a piece's own sweep counts in
  /// `pieces_seconds`): the tree's sweep with its repair rounds, of which CGAL's whole-mesh tests
  /// (floats and doubles side by side, each round that assembles), the pieces' sweeps, and their
  /// unions with the tree (corefinements, the tests of the regions they changed, any retries).
  double sweep_seconds = 0.0;
  double test_seconds = 0.0;
  double pieces_seconds = 0.0;
  double union_seconds = 0.0;
};

/// @throws OptionError naming the first option of `options` out of range (what sweep_mesh refuses).
void check_sweep_options(const SweepOptions& options);

/// Sweeps the branches of a skeleton with radii into one closed, 2-manifold, outward-oriented
/// triangle mesh. Ring polygons keep each cross section's area (so volumes are exact for straight
/// branches). The mesh is in the skeleton's local frame.
/// @throws InputError when the skeleton is empty, not a tree, or has a radius that is not positive.
/// @throws OptionError for options out of range.
TreeMesh sweep_mesh(const Skeleton& skeleton, const SweepOptions& options = {}, SweepStats* stats = nullptr);

}  // namespace treeskel::modeling
