// One attempt of the sweep to build the mesh of a skeleton: its surface as a triangle soup in parts
// (a join's hull, a tube's band between two rings, a cap or a tip's cone), and what is asked of it:
// the mesh it makes, the parts that cross one another, and how far a part must thin to clear another.
#pragma once

#include "treeskel/modeling/tree_mesh.h"
#include "treeskel/skeleton.h"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

namespace treeskel::modeling::detail {

/// Outcome of one attempt to build the mesh of a (pruned, scaled) skeleton.
struct Attempt {
  std::size_t absorbed = 0;    // twigs too short to leave their join's hull, left inside it
  std::size_t thinned = 0;     // the root's chain thinned so that the joins at both its ends fit
  std::size_t dropped = 0;     // branches left out of this sweep where their joins did not fit
  std::size_t straightened = 0;  // branches between two forks swept straight (they doubled back)
  std::vector<NodeId> shrink;  // subtrees (by their top node) to thin, then try again
  std::vector<NodeId> detached;  // subtrees (by their top node) left out of this sweep, swept apart
  // The surface as a triangle soup, in parts: a join's hull, a tube's band between two adjacent
  // rings, its base cap or its tip cone. Parts that share a ring meet only at that ring (a ring's
  // plane has its band on one side and the next band or the join on the other), so only parts that
  // share no ring are tested against each other. A part against itself is not tested: a band that
  // folds where a branch kinks is left to CGAL's test of the whole mesh.
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<std::size_t, 3>> faces;
  std::vector<NodeId> face_owner;  // per face: top node of the branch or join that made it
  std::vector<double> owner_radius;  // per face: that branch's or join's radius
  std::vector<std::size_t> face_part;  // per face: its part
  std::vector<std::vector<std::size_t>> part_rings;  // per part: its rings (by their first vertex)
  /// Per part: a segment the part lies within `radius` of (radius -1 for a join's hull).
  struct Axis {
    Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();
    double radius = -1.0;
    std::ptrdiff_t tube = -1;  // the tube it belongs to (-1: a hull)
  };
  std::vector<Axis> part_axis;
  /// Per tube: its joins at either end (-1: none) and its parts, [first_part, end_part).
  struct TubeParts {
    std::array<std::ptrdiff_t, 2> joins{-1, -1};
    std::size_t first_part = 0, end_part = 0;
  };
  std::vector<TubeParts> tube_parts;
  std::size_t branches = 0, junctions = 0, merged_forks = 0;
};

/// The attempt's triangles as one OpenMesh mesh; faces OpenMesh refuses (a non-manifold spot) ask
/// for their branch to be thinned instead (`attempt.shrink`), and the result is then empty.
std::optional<TreeMesh> assemble(Attempt& attempt);

/// Pairs of faces, one pair for each two parts of the attempt that cross (see `Attempt`): the parts'
/// boxes are matched first, then the faces of two overlapping parts that share no ring are tested
/// exactly against each other. Parts that share a ring are not tested: they meet only at it.
std::vector<std::pair<std::size_t, std::size_t>> crossing_parts(const Attempt& attempt);

/// Factor by which part `x`'s radii must shrink to clear part `y`, from their axes (a part lies
/// within its radius of its axis): 0.97 (d - r_y) / r_x, at most 0.95; none when either is a hull,
/// which has no axis. Two tubes that share no join are compared over their whole length (where one
/// runs inside the other, only the ends of that stretch cross the other's surface).
std::optional<double> clearing_factor(const Attempt& attempt, std::size_t x, std::size_t y);

}  // namespace treeskel::modeling::detail
