// How a fork's join is laid out: the arms (branch chains) that meet there, each with a ring some
// distance along its chain, pushed out from the fork until the plane of every ring has all the
// others behind it (the rings then bound a convex hull, the join's surface, without crossing).
#pragma once

#include "tube.h"

#include "treeskel/skeleton.h"

#include <Eigen/Core>

#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

namespace treeskel::modeling::detail {

/// A join's rings are pushed out from it, each step by how far its plane has another ring before
/// it, this many times at most.
constexpr int kMaxJunctionIterations = 80;
/// A ring starts this many of its radii out from its join.
constexpr double kFirstRingRadii = 0.25;
/// Every other ring of a join lies behind a ring's plane by this many of its radii.
constexpr double kRingClearanceRadii = 0.02;
/// A ring whose plane faces another's moves by its overlap over (1 - the cosine between them), the
/// divisor at least this: nearly facing rings move ten times their overlap a step, no more.
constexpr double kLeastFacingDivisor = 0.1;
/// Which arm a join gives up when rings run out of room: how far past its room each has gone, a
/// twig's counted this many times (twigs go first).
constexpr double kTwigOverrunWeight = 2.0;

/// A branch chain with one end in a join.
struct Arm {
  enum Kind { leaf, inner, root } kind = leaf;  ///< a twig, a chain to another join, the base chain
  std::size_t chain = 0;
  bool forward = true;    ///< leaves its join at the chain's start (else at its end, toward the root)
  double available = 0.0; ///< how far along the chain its ring may go
  double d = 0.0;         ///< ring distance from the join along the chain
  double neck = 1.0;      ///< ring radius factor at the join (below 1 at narrow forks)
};

/// A join: its forks (several where forks were merged into one join) and its arms.
struct Cluster {
  std::vector<NodeId> nodes;
  std::vector<Arm> arms;
};

/// The ring of `arm` at distance `d` from its join along `line` (its chain's polyline), `sides`
/// sides, narrowed by its neck, and its outward normal (away from the join).
std::pair<Ring, Eigen::Vector3d> arm_ring(const Arm& arm, double d, const Polyline& line, int sides);

/// Pushes each arm's ring of `cl` out (setting `Arm::d`, from kFirstRingRadii of its radius) until
/// every ring's plane has all other rings behind it by kRingClearanceRadii of its radius, each ring
/// within `reach` of the join and its `available` room. `lines` and `sides`: per chain. Returns the
/// arm that ran out of room (a twig's overrun counted kTwigOverrunWeight times), if one did;
/// `partner[i]` is then the arm whose ring most crosses arm i's plane.
std::optional<std::size_t> place_rings(Cluster& cl, double reach, const std::vector<Polyline>& lines,
                                       const std::vector<int>& sides, double eps, std::vector<std::size_t>& partner);

}  // namespace treeskel::modeling::detail
