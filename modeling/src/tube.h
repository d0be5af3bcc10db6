// The tube geometry of the sweep: a chain's polyline with a rotation-minimizing frame, and the rings
// (regular polygons of the circle's area) laid across it, with the tests of whether two rings can be
// joined without the tube crossing itself.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <vector>

namespace treeskel::modeling::detail {

constexpr double kPi = 3.14159265358979323846;

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

}  // namespace treeskel::modeling::detail
