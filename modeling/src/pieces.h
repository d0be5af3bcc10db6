// The limbs the sweep of a tree leaves no room for (at a join, or by a crossing its repair could not
// clear): each swept on its own, with everything it carries, and united with the tree.
#pragma once

#include "treeskel/modeling/sweep.h"
#include "treeskel/skeleton.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <chrono>
#include <cstddef>
#include <vector>

namespace treeskel::modeling::detail {

/// Wall time since `start`, in seconds (SweepStats' stage times).
inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// The offset to the frame files of this skeleton's mesh hold (local + offset): the input's, unless
/// 32-bit floats would round it by more than 1e-5 of the tree's size (then local, zero).
Eigen::Vector3d file_frame(const Skeleton& skeleton);

/// How a sweep closes the tube of its root's branch where no join holds the root.
enum class BaseCap {
  flat,  ///< a disc across the tube: the tree's own base, on the ground
  /// A shallow cone, its apex a quarter of a radius into the tube from its first ring and as much
  /// aside, toward where the branch goes (turned a little about the axis): a piece's base, inside
  /// its parent where the union removes it. Two limbs swept apart from one fork start at one point
  /// of their parent's path (`piece_of`), and flat discs there lay in one plane: corefinement went
  /// through their overlap in exact numbers (0.1-0.2 s a union of two such pieces of a few thousand
  /// faces on AdTree's Lille_2, where the others took a few milliseconds). The cones of two limbs
  /// that leave apart do not share a face's plane.
  hidden,
};

/// What every piece of a tree keeps of the whole tree when it is swept on its own.
struct TreeScale {
  /// Radii under it are raised to it (see `sweep_in_frame`).
  double floor_radius = 0.0;
  /// A branch that starts at least this thick is a limb (`max_drop_radius` of the tree's thickest
  /// radius): it is thinned further than a twig before it is swept apart, and where the joins at both
  /// its ends cannot fit, its forks share a hull. Taken from a piece's own thickest branch instead,
  /// every twig of a piece of twigs was a limb: forks 0.4 m apart shared a hull that passed the fork
  /// between them by, and the limbs swept apart from that fork lay beside the tree (TreeLS's spruce,
  /// LPine1's tree 11).
  double limb_radius = 0.0;
  /// The wood of the whole tree (the frustums between its nodes, radii raised to the floor): a branch
  /// that carries `max_thinned_share` of it or more is swept apart, not thinned (see `SweepOptions`);
  /// 0: not known, and no branch is swept apart for what it carries.
  double wood_volume = 0.0;
  /// The longest a band of a tube may run between two rings (a share of the whole tree's extent, so
  /// that a piece's bands are as long as the tree's); 0: no limit.
  double longest_band = 0.0;
};

/// `sweep_mesh` with the frame files hold and the floor radius given (a piece of a tree is checked
/// in the tree's frame and keeps the tree's floor; a negative floor: `min_relative_radius` of the
/// thickest radius or `min_extent_radius` of the extent, the larger). A branch the repair would
/// thin below the floor (at its start) is swept apart instead.
TreeMesh sweep_in_frame(const Skeleton& skeleton, const SweepOptions& options, const Eigen::Vector3d& frame,
                        double floor_radius, SweepStats* stats);

/// The sweep of what of `skeleton` fits together (radii under the floor raised to it); the
/// branches a join or a crossing left no room for are appended to `apart` (each as `piece_of` cuts
/// it, with all it carries), not swept, and `kept` (if given) receives the skeleton the mesh is of.
/// With `unite_apart` off they are counted in `pieces_failed` instead. `base` closes the root's
/// branch (see BaseCap).
TreeMesh sweep_part(const Skeleton& skeleton, const SweepOptions& options, const Eigen::Vector3d& frame,
                    const TreeScale& scale, SweepStats& st, std::vector<Skeleton>& apart, Skeleton* kept,
                    BaseCap base = BaseCap::flat);

/// Adds to `to` the counts of `from` (a piece's sweep) that add up over pieces.
void add_counts(SweepStats& to, const SweepStats& from);

/// Takes back from `to` the counts of what `from`'s sweep put into the mesh (branches, joins, what
/// was thinned or swept apart), never below zero: a piece split after it was counted has its parts
/// swept and counted again. The work it took (attempts, repair rounds) stays counted.
void take_counts(SweepStats& to, const SweepStats& from);

/// The points of `mesh` (by vertex index) as the 32-bit floats they become in the frame `offset`
/// leads to, where a file holds them: where to place the vertices to test the mesh as read back.
std::vector<TreeMesh::Point> world_floats(const TreeMesh& mesh, const Eigen::Vector3d& offset);

/// Faces of `mesh` (indices, ascending) whose boxes meet one of `boxes`: where a union changed the
/// mesh, the faces a crossing it added can involve.
std::vector<std::size_t> faces_touching(const TreeMesh& mesh, const std::vector<Eigen::AlignedBox3d>& boxes);

/// How a piece that cannot be swept or united whole is split: each branch leaving its base chain's
/// end (or its root, when several leave it) apart, and the base chain in two overlapping halves.
/// Empty for a single segment, which cannot be split.
std::vector<Skeleton> split_piece(const Skeleton& piece);

/// Sweeps `pieces` (with `sweep_part`; what each leaves apart becomes a piece too) and unites them
/// with `mesh`. `frame` is the offset to the frame files hold (local + frame), where the union is
/// rounded to 32-bit floats and checked: a union may not add a crossing there. What cannot be
/// united without one is split and its parts united, down to single segments; those are counted in
/// `pieces_failed`.
TreeMesh add_pieces(TreeMesh mesh, const std::vector<Skeleton>& pieces, const SweepOptions& options,
                    const Eigen::Vector3d& frame, const TreeScale& scale, SweepStats& st);

}  // namespace treeskel::modeling::detail
