#include "tube.h"

#include "treeskel/error.h"
#include "treeskel/geometry.h"

#include <Eigen/Geometry>

#include <algorithm>

namespace treeskel::modeling::detail {

using Eigen::Vector3d;

double area_factor(int sides) {
  const double n = sides;
  return std::sqrt(2.0 * kPi / (n * std::sin(2.0 * kPi / n)));
}

Vector3d transport(const Vector3d& u, const Vector3d& from, const Vector3d& to) {
  const Vector3d v = Eigen::Quaterniond::FromTwoVectors(from, to) * u;
  const Vector3d ortho = v - v.dot(to) * to;
  return ortho.norm() > 1e-12 ? Vector3d(ortho.normalized()) : Vector3d(to.unitOrthogonal());
}

namespace {

/// Whether a path going `in` and then `out` turns back by more than 120 degrees.
bool turns_back(const Vector3d& in, const Vector3d& out) { return in.dot(out) < -0.5 * in.norm() * out.norm(); }

/// Drops `count` points of `pl` from the `i`th on.
void erase_points(Polyline& pl, std::size_t i, std::size_t count) {
  const auto from = static_cast<std::ptrdiff_t>(i), to = static_cast<std::ptrdiff_t>(i + count);
  pl.p.erase(pl.p.begin() + from, pl.p.begin() + to);
  pl.r.erase(pl.r.begin() + from, pl.r.begin() + to);
}

}  // namespace

Polyline make_polyline(const std::vector<Vector3d>& points, const std::vector<double>& radii, double eps) {
  Polyline pl;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const bool last = i + 1 == points.size();
    if (!pl.p.empty() && (points[i] - pl.p.back()).norm() <= eps) {
      if (last && pl.p.size() > 1) {  // keep the true end
        pl.p.back() = points[i];
        pl.r.back() = radii[i];
      }
      continue;
    }
    pl.p.push_back(points[i]);
    pl.r.push_back(radii[i]);
  }
  // A skeleton that wanders inside its own branch (the medians of a thick trunk zigzagging across it,
  // or stepping down and up again) gives a tube through itself: a point closer than kStepRadii
  // radii to the last point kept is dropped, and so is the last point kept when the end is that
  // close to it (never the ends themselves).
  if (pl.p.size() > 2) {
    Polyline walked;
    walked.p.push_back(pl.p.front());
    walked.r.push_back(pl.r.front());
    for (std::size_t i = 1; i + 1 < pl.p.size(); ++i)
      if ((pl.p[i] - walked.p.back()).norm() >= kStepRadii * std::max(pl.r[i], walked.r.back())) {
        walked.p.push_back(pl.p[i]);
        walked.r.push_back(pl.r[i]);
      }
    if (walked.p.size() > 1 && (pl.p.back() - walked.p.back()).norm() < kStepRadii * std::max(pl.r.back(), walked.r.back())) {
      walked.p.pop_back();
      walked.r.pop_back();
    }
    walked.p.push_back(pl.p.back());
    walked.r.push_back(pl.r.back());
    pl.p = std::move(walked.p);
    pl.r = std::move(walked.r);
  }
  // A polyline that doubles back on itself would give a tube through itself at any radius: points
  // where it turns by more than 120 degrees are dropped (never the ends).
  for (bool changed = true; changed && pl.p.size() > 2;) {
    changed = false;
    for (std::size_t i = 1; i + 1 < pl.p.size(); ++i) {
      if (turns_back(pl.p[i] - pl.p[i - 1], pl.p[i + 1] - pl.p[i])) {
        erase_points(pl, i, 1);
        changed = true;
        break;
      }
    }
  }
  // ... and so does one that doubles back in two turns, across a step shorter than two radii (a
  // hairpin within its own branch): the two points of that step are dropped. A thick limb of the
  // LPine1 plot's tree 1 that turns back in two bends of 105 and 50 degrees crossed itself, no
  // ring after the turn fitted, and its tube ended in a fin where the rest of the limb should be.
  for (bool changed = true; changed && pl.p.size() > 3;) {
    changed = false;
    for (std::size_t i = 1; i + 2 < pl.p.size(); ++i) {
      const double step = (pl.p[i + 1] - pl.p[i]).norm();
      if (step < 2.0 * std::max(pl.r[i], pl.r[i + 1]) && turns_back(pl.p[i] - pl.p[i - 1], pl.p[i + 2] - pl.p[i + 1])) {
        erase_points(pl, i, 2);
        changed = true;
        break;
      }
    }
  }
  const std::size_t n = pl.p.size();
  pl.s.assign(n, 0.0);
  for (std::size_t i = 1; i < n; ++i) pl.s[i] = pl.s[i - 1] + (pl.p[i] - pl.p[i - 1]).norm();
  if (n < 2) return pl;
  pl.t.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vector3d in = i > 0 ? Vector3d((pl.p[i] - pl.p[i - 1]).normalized()) : Vector3d::Zero();
    const Vector3d out = i + 1 < n ? Vector3d((pl.p[i + 1] - pl.p[i]).normalized()) : Vector3d::Zero();
    const Vector3d sum = in + out;
    pl.t[i] = sum.norm() > 1e-9 ? Vector3d(sum.normalized()) : (out.isZero() ? in : out);
  }
  pl.u.resize(n);
  pl.u[0] = pl.t[0].unitOrthogonal();
  for (std::size_t i = 1; i < n; ++i) pl.u[i] = transport(pl.u[i - 1], pl.t[i - 1], pl.t[i]);
  return pl;
}

Ring ring_at(const Polyline& pl, double s, int sides) {
  const std::size_t n = pl.p.size();
  TREESKEL_REQUIRE(n >= 2, "a branch of no length has no ring");
  s = std::clamp(s, 0.0, pl.length());
  std::size_t i = static_cast<std::size_t>(std::upper_bound(pl.s.begin(), pl.s.end(), s) - pl.s.begin());
  i = i == 0 ? 0 : i - 1;
  if (i + 1 >= n) i = n - 2;
  Ring ring;
  ring.sides = sides;
  const double len = pl.s[i + 1] - pl.s[i];
  const double f = len > 0.0 ? (s - pl.s[i]) / len : 0.0;
  ring.centre = (1.0 - f) * pl.p[i] + f * pl.p[i + 1];
  const double radius = (1.0 - f) * pl.r[i] + f * pl.r[i + 1];
  ring.radius = radius * area_factor(sides);
  if (f <= 1e-12) {
    ring.normal = pl.t[i];
    ring.u = pl.u[i];
  } else if (f >= 1.0 - 1e-12) {
    ring.normal = pl.t[i + 1];
    ring.u = pl.u[i + 1];
  } else {
    ring.normal = (pl.p[i + 1] - pl.p[i]).normalized();
    ring.u = transport(pl.u[i], pl.t[i], ring.normal);
  }
  return ring;
}

double reach_beyond(const Ring& a, const Vector3d& na, const Ring& b) {
  const double c = std::clamp(na.dot(b.normal), -1.0, 1.0);
  return (b.centre - a.centre).dot(na) + b.radius * std::sqrt(std::max(0.0, 1.0 - c * c));
}

bool compatible(const Ring& a, const Ring& b, double margin) {
  return -reach_beyond(a, -a.normal, b) > margin && reach_beyond(b, b.normal, a) < -margin;
}

bool straight_past(const Polyline& pl, const Ring& prev, double prev_s, std::size_t i, double s1, const Ring& last,
                   const RingRule& rule) {
  const bool to_last = i + 2 >= pl.p.size() || pl.s[i + 1] >= s1;
  const Vector3d end = to_last ? last.centre : pl.p[i + 1];
  const double end_s = to_last ? s1 : pl.s[i + 1];
  const double end_r = to_last ? last.radius / area_factor(last.sides) : pl.r[i + 1];
  const double start_r = prev.radius / area_factor(prev.sides);
  const Vector3d axis = end - prev.centre;
  const double length = axis.norm();
  if (!(length > rule.eps) || !(end_s > prev_s)) return false;
  if (rule.longest_band > 0.0 && length > rule.longest_band) return false;
  if (axis.dot(prev.normal) < std::cos(rule.max_turn) * length) return false;
  for (std::size_t k = i; k > 0 && pl.s[k] > prev_s; --k) {
    const double f = (pl.s[k] - prev_s) / (end_s - prev_s);
    const double taper = (1.0 - f) * start_r + f * end_r;
    if (std::abs(pl.r[k] - taper) > kTaperShare * taper) return false;
    if (point_segment_distance(pl.p[k], prev.centre, end) > kStrayRadii * std::min(pl.r[k], taper)) return false;
  }
  return true;
}

bool lay_rings(const Polyline& pl, double s0, double s1, const Ring& first, const Ring& last, int sides,
               const RingRule& rule, std::vector<Ring>& rings) {
  const double margin_scale = 0.01;
  rings.assign(1, first);
  double prev_s = s0;
  for (std::size_t i = 1; i + 1 < pl.p.size(); ++i) {
    if (pl.s[i] <= s0 || pl.s[i] >= s1) continue;
    const Ring candidate = ring_at(pl, pl.s[i], sides);
    const Ring& prev = rings.back();
    const double r = std::max(candidate.radius, prev.radius);
    const bool far = (candidate.centre - prev.centre).norm() >= rule.spacing * r;
    const bool turned = std::acos(std::clamp(candidate.normal.dot(prev.normal), -1.0, 1.0)) > rule.max_turn;
    if (!far && !turned) continue;
    if (!turned && straight_past(pl, prev, prev_s, i, s1, last, rule)) continue;
    if (!compatible(prev, candidate, margin_scale * r + rule.eps)) continue;
    rings.push_back(candidate);
    prev_s = pl.s[i];
  }
  while (rings.size() > 1 &&
         !compatible(rings.back(), last, margin_scale * std::max(rings.back().radius, last.radius) + rule.eps))
    rings.pop_back();
  return compatible(rings.back(), last, rule.eps);
}

double tip_arc(const Polyline& pl, double s0) {
  const double length = pl.length();
  return std::max(s0 + 0.6 * (length - s0), length - 0.5 * pl.r.back());
}

}  // namespace treeskel::modeling::detail
