// The tube geometry of the sweep: a chain's polyline with a rotation-minimizing frame, the rings
// (regular polygons of the circle's area) laid across it, the tests of whether two rings can be
// joined without the tube crossing itself, and where along a branch its tube lays a ring.
#pragma once

#include "treeskel/geometry.h"

#include <Eigen/Core>
#include <Eigen/Geometry>  // Ring::vertex takes a cross product

#include <cmath>
#include <cstddef>
#include <vector>

namespace treeskel::modeling::detail {

/// Circumradius factor that gives a regular n-gon the area of the circle it stands for.
double area_factor(int sides);

/// A chain's polyline with its arc length and a rotation-minimizing frame at every point.
struct Polyline {
  std::vector<Eigen::Vector3d> p, t, u;  // position, tangent (travel direction), frame normal
  std::vector<double> r, s;              // radius, arc length from the start
  double length() const { return s.back(); }
};

/// A ring of the sweep: a regular polygon across the travel direction.
struct Ring {
  Eigen::Vector3d centre, normal, u;
  double radius = 0.0;  // vertex radius (area-preserving)
  int sides = 0;
  Eigen::Vector3d vertex(int k) const {
    const double a = 2.0 * kPi * k / sides;
    const Eigen::Vector3d w = normal.cross(u);
    return centre + radius * (std::cos(a) * u + std::sin(a) * w);
  }
};

/// `u` (across `from`) carried to be across `to` by the rotation that turns `from` into `to`.
Eigen::Vector3d transport(const Eigen::Vector3d& u, const Eigen::Vector3d& from, const Eigen::Vector3d& to);

/// Points of a branch's polyline are kept at least this many radii apart (the larger of the two
/// points' radii), the ends always.
constexpr double kStepRadii = 1.0;

/// The polyline through `points` with their radii: points within `eps` of the previous one are merged
/// (the last point kept), points closer than kStepRadii radii to the previous one kept dropped,
/// points where it turns by more than 120 degrees dropped, and the two points of a step shorter
/// than two radii across which it turns back by more than 120 degrees (a hairpin) dropped (never
/// the ends).
Polyline make_polyline(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& radii, double eps);

/// The ring at arc length `s` (clamped to the polyline), `sides` sides, of the interpolated radius.
Ring ring_at(const Polyline& pl, double s, int sides);

/// Largest signed distance of ring `b`'s circle from the plane of ring `a` (normal `na`).
double reach_beyond(const Ring& a, const Eigen::Vector3d& na, const Ring& b);

/// Ring `b` lies wholly ahead of ring `a` and `a` wholly behind `b`, by more than `margin` (no
/// crossing between them).
bool compatible(const Ring& a, const Ring& b, double margin);

/// Where a tube lays its rings along a branch (`lay_rings`).
struct RingRule {
  double spacing = 0.75;      ///< a ring where the branch has run this many radii since the last one ...
  double max_turn = 0.3;      ///< ... or turned by more than this (radians) ...
  double longest_band = 0.0;  ///< ... or a band would otherwise run longer than this (0: no limit)
  double eps = 0.0;           ///< lengths up to this are none
};

/// Along a branch, a ring is left out where the tube running straight past it keeps the skeleton
/// within this many of its radii of the tube's axis: inside the tube, whose polygon (as large as
/// the circle) reaches 0.78 of the radius across at 3 sides and 0.95 at 6 ...
constexpr double kStrayRadii = 0.5;
/// ... and the radius within this share of the straight taper between the rings kept.
constexpr double kTaperShare = 0.03;

/// Whether the tube may run straight from `prev` (at arc `prev_s`) past point `i` of the polyline
/// to the point after it (or to `last`, at `s1`): every point of the branch in between lies within
/// kStrayRadii of its radius of that straight axis, the radius within kTaperShare of the straight
/// taper, the axis turns from `prev`'s by at most `rule.max_turn`, and the band is no longer than
/// `rule.longest_band`. A twig raised to the floor radius is many radii long between the skeleton's
/// nodes, and a ring at each node, where it runs straight, gave most of a crown's triangles (92% on
/// AdTree's Paris_Luxembourg_1).
bool straight_past(const Polyline& pl, const Ring& prev, double prev_s, std::size_t i, double s1, const Ring& last,
                   const RingRule& rule);

/// The rings of a tube from `first` (at arc `s0`) to `last` (at `s1`), `sides` sides each: one at
/// each point of the polyline between them where the branch has run or turned enough (`rule`) and
/// the tube may not run straight past (`straight_past`), none crossing the one before or `last`.
/// False (and `rings` up to the last one that fits) when the end rings still cross.
bool lay_rings(const Polyline& pl, double s0, double s1, const Ring& first, const Ring& last, int sides,
               const RingRule& rule, std::vector<Ring>& rings);

/// Arc length of the last ring of a chain ending in a tip, its first ring at `s0`.
double tip_arc(const Polyline& pl, double s0);

}  // namespace treeskel::modeling::detail
