#include "treeskel/cpc.h"

#include "treeskel/level_sets.h"
#include "thinned.h"

#include <Eigen/Eigenvalues>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace treeskel {

namespace {

using Evaluation = CpcObjective;

/// F(v) with λ = w / μ(v) held fixed, and optionally its gradient and Hessian.
template <class Get>
Evaluation evaluate(std::size_t m, Get get, const Eigen::Vector3d& v, const Eigen::Vector3d& centroid,
                    double weight, bool derivatives) {
  double sum = 0.0, sum_sq = 0.0;
  double u_sum[3] = {0.0, 0.0, 0.0};
  double h_sum[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};  // Σ (I - u uᵀ) / d: xx yy zz xy xz yz (symmetric)
  const double floor_distance = 1e-12;
  // Adds one point, given d = max(|v - p|, floor) and u = (v - p) / d.
  const auto add = [&](double d, double ux, double uy, double uz) {
    sum += d;
    sum_sq += d * d;
    if (!derivatives) return;
    u_sum[0] += ux;
    u_sum[1] += uy;
    u_sum[2] += uz;
    h_sum[0] += (1.0 - ux * ux) / d;
    h_sum[1] += (1.0 - uy * uy) / d;
    h_sum[2] += (1.0 - uz * uz) / d;
    h_sum[3] += (0.0 - ux * uy) / d;
    h_sum[4] += (0.0 - ux * uz) / d;
    h_sum[5] += (0.0 - uy * uz) / d;
  };
  std::size_t i = 0;
#if defined(__SSE2__)
  // Two points at a time, as in the L1-median: each value is the same IEEE operation as the plain
  // code's and the sums are taken in the same order, so the result has the same bits.
  const __m128d vx = _mm_set1_pd(v.x()), vy = _mm_set1_pd(v.y()), vz = _mm_set1_pd(v.z());
  const __m128d lowest = _mm_set1_pd(floor_distance);
  for (; i + 1 < m; i += 2) {
    const Eigen::Vector3d& a = get(i);
    const Eigen::Vector3d& b = get(i + 1);
    const __m128d dx = _mm_sub_pd(vx, _mm_set_pd(b.x(), a.x())), dy = _mm_sub_pd(vy, _mm_set_pd(b.y(), a.y())),
                  dz = _mm_sub_pd(vz, _mm_set_pd(b.z(), a.z()));
    const __m128d norm = _mm_sqrt_pd(_mm_add_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)), _mm_mul_pd(dz, dz)));
    const __m128d d = _mm_max_pd(norm, lowest);  // std::max's value: the two differ only when equal
    alignas(16) double dv[2], ux[2] = {0.0, 0.0}, uy[2] = {0.0, 0.0}, uz[2] = {0.0, 0.0};
    _mm_store_pd(dv, d);
    if (derivatives) {
      _mm_store_pd(ux, _mm_div_pd(dx, d));
      _mm_store_pd(uy, _mm_div_pd(dy, d));
      _mm_store_pd(uz, _mm_div_pd(dz, d));
    }
    add(dv[0], ux[0], uy[0], uz[0]);
    add(dv[1], ux[1], uy[1], uz[1]);
  }
#endif
  for (; i < m; ++i) {
    const Eigen::Vector3d diff = v - get(i);
    const double d = std::max(diff.norm(), floor_distance);
    add(d, diff.x() / d, diff.y() / d, diff.z() / d);
  }
  const Eigen::Vector3d u_mean_sum(u_sum[0], u_sum[1], u_sum[2]);
  Eigen::Matrix3d h_mean;
  h_mean << h_sum[0], h_sum[3], h_sum[4], h_sum[3], h_sum[1], h_sum[5], h_sum[4], h_sum[5], h_sum[2];
  const double inv_m = 1.0 / static_cast<double>(m);
  Evaluation e;
  e.mean = sum * inv_m;
  const double variance = std::max(sum_sq * inv_m - e.mean * e.mean, 0.0);
  const double lambda = weight / std::max(e.mean, floor_distance);
  e.value = e.mean + lambda * variance;
  if (derivatives) {
    const Eigen::Vector3d u_mean = u_mean_sum * inv_m;
    h_mean *= inv_m;
    // d(mean)/dv = ū, d(mean of d²)/dv = 2(v - x̄), d(μ²)/dv = 2μū.
    e.gradient = u_mean + lambda * (2.0 * (v - centroid) - 2.0 * e.mean * u_mean);
    e.hessian = h_mean + lambda * (2.0 * Eigen::Matrix3d::Identity() - 2.0 * u_mean * u_mean.transpose() -
                                   2.0 * e.mean * h_mean);
  }
  return e;
}

template <class Get>
Eigen::Vector3d minimise(std::size_t count, Get get_all, const Eigen::Vector3d& start, const CpcOptions& options,
                         const Eigen::Vector3d& axis) {
  thread_local std::vector<Eigen::Vector3d> points;  // this thread's copy of the set, reused
  detail::copy_thinned(count, options.max_points, get_all, points);
  const std::size_t m = points.size();
  auto get = [&](std::size_t i) -> const Eigen::Vector3d& { return points[i]; };
  if (m < std::max<std::size_t>(options.min_points, 3) || options.weight <= 0.0) return start;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < m; ++i) centroid += get(i);
  centroid /= static_cast<double>(m);

  Eigen::Vector3d v = start;
  Evaluation current = evaluate(m, get, v, centroid, options.weight, true);
  const double mean0 = current.mean;
  if (mean0 <= 0.0) return start;
  // Motion is confined to the plane across the branch: project gradient and Hessian onto it, and give
  // the axis direction a unit curvature (its gradient component is zero, so it takes no step).
  const bool planar = axis.squaredNorm() > 0.0;
  const Eigen::Vector3d n = planar ? axis.normalized() : Eigen::Vector3d::Zero();
  const Eigen::Matrix3d project = Eigen::Matrix3d::Identity() - n * n.transpose();
  for (int it = 0; it < options.max_iterations; ++it) {
    // Newton direction on the positive-definite part of the Hessian.
    const Eigen::Vector3d gradient = project * current.gradient;
    Eigen::Matrix3d hessian = project * current.hessian * project;
    if (planar) hessian += hessian.trace() * n * n.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(hessian);
    Eigen::Vector3d lambda = eig.eigenvalues();
    const double biggest = std::max(lambda.cwiseAbs().maxCoeff(), 1e-300);
    for (int k = 0; k < 3; ++k) lambda(k) = std::max(std::abs(lambda(k)), 1e-6 * biggest);
    Eigen::Vector3d step =
        -(eig.eigenvectors() * (eig.eigenvectors().transpose() * gradient).cwiseQuotient(lambda));
    step = project * step;
    const double cap = 0.5 * current.mean;  // never jump across the branch in one step
    if (step.norm() > cap) step *= cap / step.norm();

    bool moved = false;
    for (int halving = 0; halving < 20; ++halving) {
      const Eigen::Vector3d candidate = v + step;
      const Evaluation trial = evaluate(m, get, candidate, centroid, options.weight, false);
      if (trial.value < current.value) {
        v = candidate;
        moved = true;
        break;
      }
      step *= 0.5;
    }
    if (!moved || step.norm() < options.tolerance * current.mean) break;
    current = evaluate(m, get, v, centroid, options.weight, true);
  }
  if ((v - start).norm() > options.max_shift * mean0) return start;
  // Accept only a centre around which the points form a cylinder slice.
  double sum = 0.0, sum_sq = 0.0;
  for (std::size_t i = 0; i < m; ++i) {
    const double d = (v - get(i)).norm();
    sum += d;
    sum_sq += d * d;
  }
  const double mean = sum / static_cast<double>(m);
  const double spread = std::sqrt(std::max(sum_sq / static_cast<double>(m) - mean * mean, 0.0));
  if (spread > options.max_spread * mean) return start;
  return v;
}

}  // namespace

CpcObjective cpc_objective(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& v, double weight) {
  if (points.empty()) return {};
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : points) centroid += p;
  centroid /= static_cast<double>(points.size());
  return evaluate(points.size(), [&](std::size_t i) -> const Eigen::Vector3d& { return points[i]; }, v, centroid,
                  weight, true);
}

Eigen::Vector3d cpc_centre(const std::vector<Eigen::Vector3d>& positions, const std::uint32_t* first,
                           const std::uint32_t* last, const Eigen::Vector3d& start, const CpcOptions& options,
                           const Eigen::Vector3d& axis) {
  return minimise(static_cast<std::size_t>(last - first),
                  [&](std::size_t i) -> const Eigen::Vector3d& { return positions[first[i]]; }, start, options, axis);
}

void recentre_nodes(Skeleton& skeleton, const PointCloud& cloud, const CpcOptions& options) {
  auto& g = skeleton.graph;
  const std::size_t n = boost::num_vertices(g);
  const auto parent = parents_from_root(g, skeleton.root);
  std::vector<int> children(n, 0);
  std::vector<Eigen::Vector3d> child_sum(n, Eigen::Vector3d::Zero());
  for (NodeId v = 0; v < n; ++v)
    if (v != skeleton.root) {
      ++children[parent[v]];
      child_sum[parent[v]] += g[v].position;
    }
  // Branch direction at each node, from the positions before any node moves.
  std::vector<Eigen::Vector3d> axis(n, Eigen::Vector3d::Zero());
  for (NodeId v = 0; v < n; ++v) {
    if (children[v] > 1) continue;
    const Eigen::Vector3d from = v == skeleton.root ? g[v].position : g[parent[v]].position;
    const Eigen::Vector3d to = children[v] == 1 ? child_sum[v] : g[v].position;
    axis[v] = to - from;
  }
  std::vector<Eigen::Vector3d> moved(n);
  std::vector<double> radius(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 16), [&](const auto& range) {
    for (std::size_t v = range.begin(); v != range.end(); ++v) {
      const auto& node = g[v];
      moved[v] = node.position;
      if (!node.points.empty() && axis[v].squaredNorm() > 0.0)
        moved[v] = cpc_centre(cloud.positions, node.points.data(), node.points.data() + node.points.size(),
                              node.position, options, axis[v]);
      radius[v] = mean_distance(cloud.positions, node.points, moved[v]);
    }
  });
  for (NodeId v = 0; v < n; ++v) {
    g[v].position = moved[v];
    g[v].radius = radius[v];
  }
}

}  // namespace treeskel
