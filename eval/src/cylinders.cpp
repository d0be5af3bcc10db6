#include "treeskel/eval/cylinders.h"

#include "treeskel/error.h"
#include "treeskel/geometry.h"

#include <Eigen/Geometry>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace treeskel::eval {

namespace {

double axis_parameter(const Cylinder& c, const Eigen::Vector3d& p) {
  const Eigen::Vector3d ab = c.b - c.a;
  return (p - c.a).dot(ab) / ab.squaredNorm();
}

Eigen::AlignedBox3d box_of(const Cylinder& c) {
  const double r = std::max(c.radius_a, c.radius_b);
  Eigen::AlignedBox3d box(c.a.cwiseMin(c.b), c.a.cwiseMax(c.b));
  box.min().array() -= r;
  box.max().array() += r;
  return box;
}

}  // namespace

double distance_to_axis(const Cylinder& c, const Eigen::Vector3d& p) {
  const double t = std::clamp(axis_parameter(c, p), 0.0, 1.0);
  return (p - (c.a + t * (c.b - c.a))).norm();
}

bool inside(const Cylinder& c, const Eigen::Vector3d& p) {
  const double t = axis_parameter(c, p);
  if (t < 0.0 || t > 1.0) return false;
  const double r = c.radius_a + t * (c.radius_b - c.radius_a);
  return (p - (c.a + t * (c.b - c.a))).norm() < r;
}

PointCloud sample_cylinders(const std::vector<Cylinder>& cylinders, const SurfaceSampling& sampling) {
  const std::size_t k = cylinders.size();
  PointCloud cloud;
  if (k == 0 || sampling.points == 0) return cloud;
  // Lateral area of each cone frustum, and the cylinders each one can hide points in.
  std::vector<double> cumulative(k);
  double total = 0.0;
  std::vector<Eigen::AlignedBox3d> boxes(k);
  for (std::size_t i = 0; i < k; ++i) {
    const auto& c = cylinders[i];
    const double slant = std::hypot((c.b - c.a).norm(), c.radius_a - c.radius_b);
    total += M_PI * (c.radius_a + c.radius_b) * slant;
    cumulative[i] = total;
    boxes[i] = box_of(c);
  }
  // A scanner's reference distance: the nearest box (see SurfaceSampling::viewpoint).
  double d_near = 0.0;
  if (sampling.viewpoint) {
    d_near = std::numeric_limits<double>::infinity();
    for (const auto& b : boxes) d_near = std::min(d_near, b.exteriorDistance(*sampling.viewpoint));
    if (!(d_near > 0.0)) throw OptionError("sample_cylinders: the viewpoint lies inside the tree's boxes");
  }
  std::vector<std::vector<std::uint32_t>> near(k);
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t j = 0; j < k; ++j)
      if (i != j && boxes[i].intersects(boxes[j])) near[i].push_back(static_cast<std::uint32_t>(j));

  // Whether the scanner at `eye` records the surface point `p` (normal `n`, on cylinder `own`) given a
  // uniform draw `u`: facing, kept with the scanner's density, and no other cylinder on the line of sight.
  const auto seen_from = [&](const Eigen::Vector3d& eye, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                             std::size_t own, double u) {
    const Eigen::Vector3d to_eye = eye - p;
    const double d = to_eye.norm();
    const double cosine = n.dot(to_eye) / d;
    if (cosine <= 0.0 || u >= cosine * (d_near / d) * (d_near / d)) return false;
    const Eigen::Vector3d inverse = to_eye.cwiseInverse();
    for (std::size_t j = 0; j < k; ++j) {
      if (j == own) continue;
      // Slab test of the sight line against the box first; then the line's distance to the axis.
      const Eigen::Vector3d t0 = (boxes[j].min() - p).cwiseProduct(inverse), t1 = (boxes[j].max() - p).cwiseProduct(inverse);
      const double enter = t0.cwiseMin(t1).maxCoeff(), leave = t0.cwiseMax(t1).minCoeff();
      if (enter > leave || leave < 0.0 || enter > 1.0) continue;
      const auto& c = cylinders[j];
      if (segment_segment_distance(p, eye, c.a, c.b) < std::max(c.radius_a, c.radius_b)) return false;
    }
    return true;
  };

  // Points are drawn in fixed-size chunks, each from its own seeded generator, so the result does not
  // depend on the thread count. Rejected points are replaced by drawing more chunks.
  constexpr std::size_t chunk = 4096;
  std::vector<Eigen::Vector3d> accepted;
  accepted.reserve(sampling.points);
  std::uint64_t next_chunk = 0;
  while (accepted.size() < sampling.points) {
    const std::size_t missing = sampling.points - accepted.size();
    const std::size_t chunks = std::max<std::size_t>(1, (missing + chunk - 1) / chunk + 1);
    std::vector<std::vector<Eigen::Vector3d>> drawn(chunks);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks), [&](const auto& range) {
      for (std::size_t q = range.begin(); q != range.end(); ++q) {
        std::mt19937_64 rng(sampling.seed * 0x9E3779B97F4A7C15ULL + next_chunk + q);
        std::uniform_real_distribution<double> unit(0.0, 1.0);
        std::normal_distribution<double> gauss(0.0, 1.0);
        for (std::size_t s = 0; s < chunk; ++s) {
          const double pick = unit(rng) * total;
          const std::size_t i = std::min<std::size_t>(
              std::upper_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin(), k - 1);
          const auto& c = cylinders[i];
          const Eigen::Vector3d axis = (c.b - c.a).normalized();
          const Eigen::Vector3d u = axis.unitOrthogonal(), v = axis.cross(u);
          const double angle = unit(rng) * 2.0 * M_PI;
          // Along a frustum the area grows with the radius: draw t with density ∝ r(t).
          double t = unit(rng);
          const double ra = c.radius_a, rb = c.radius_b;
          if (std::abs(rb - ra) > 1e-12 * (ra + rb)) t = (std::sqrt(ra * ra + t * (rb * rb - ra * ra)) - ra) / (rb - ra);
          const double noise = sampling.noise > 0.0 ? sampling.noise * gauss(rng) : 0.0;
          const Eigen::Vector3d normal = std::cos(angle) * u + std::sin(angle) * v;
          if (sampling.facing && normal.dot(*sampling.facing) < 0.0) continue;
          const double r = ra + t * (rb - ra);
          const Eigen::Vector3d p = c.a + t * (c.b - c.a) + (r + noise) * normal;
          const Eigen::Vector3d on_surface = c.a + t * (c.b - c.a) + r * normal;
          bool hidden = false;
          for (auto j : near[i])
            if (inside(cylinders[j], on_surface)) {
              hidden = true;
              break;
            }
          if (!hidden && sampling.viewpoint && !seen_from(*sampling.viewpoint, on_surface, normal, i, unit(rng))) hidden = true;
          if (!hidden) drawn[q].push_back(p);
        }
      }
    });
    next_chunk += chunks;
    std::size_t got = 0;
    for (auto& d : drawn) {
      got += d.size();
      for (const auto& p : d) {
        if (accepted.size() == sampling.points) break;
        accepted.push_back(p);
      }
    }
    if (got == 0) throw Error("sample_cylinders: no sampled point is on the visible surface");
  }
  cloud.positions = std::move(accepted);
  return cloud;
}

}  // namespace treeskel::eval
