#include "treeskel/l1_median.h"

#include "thinned.h"

#include <algorithm>
#include <numeric>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace treeskel {

namespace {

template <class Get>
Eigen::Vector3d weiszfeld(std::size_t count, Get get_all, const L1MedianOptions& options) {
  if (count == 0) return Eigen::Vector3d::Zero();
  thread_local std::vector<Eigen::Vector3d> points;  // this thread's copy of the set, reused
  detail::copy_thinned(count, options.max_points, get_all, points);
  const std::size_t n = points.size();
  auto get = [&](std::size_t i) -> const Eigen::Vector3d& { return points[i]; };
  Eigen::Vector3d y = Eigen::Vector3d::Zero();
  Eigen::Vector3d lo = get(0), hi = get(0);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& p = get(i);
    y += p;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  y /= static_cast<double>(n);
  const double extent = (hi - lo).norm();
  if (n <= 2 || extent == 0.0) return y;  // the mean is a median of one or two points
  const double stop = options.tolerance * extent;
  const double coincide = 1e-12 * extent;
  for (int it = 0; it < options.max_iterations; ++it) {
    Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
    double weight_sum = 0.0;
    int coincident = 0;
    // Adds point p's pull, given its distance d and p / d, 1 / d.
    const auto pull = [&](double d, double qx, double qy, double qz, double w) {
      if (d <= coincide) {
        ++coincident;
        return;
      }
      weighted.x() += qx;
      weighted.y() += qy;
      weighted.z() += qz;
      weight_sum += w;
    };
    std::size_t i = 0;
#if defined(__SSE2__)
    // Two points at a time: the square root and the four divisions of a point are the step's cost,
    // and the packed instructions do two points' for the price of about one. Each value is the same
    // IEEE operation as the scalar code's, and the sums are taken in the same order: the same bits.
    const __m128d yx = _mm_set1_pd(y.x()), yy = _mm_set1_pd(y.y()), yz = _mm_set1_pd(y.z()), one = _mm_set1_pd(1.0);
    for (; i + 1 < n; i += 2) {
      const Eigen::Vector3d& a = get(i);
      const Eigen::Vector3d& b = get(i + 1);
      const __m128d px = _mm_set_pd(b.x(), a.x()), py = _mm_set_pd(b.y(), a.y()), pz = _mm_set_pd(b.z(), a.z());
      const __m128d dx = _mm_sub_pd(px, yx), dy = _mm_sub_pd(py, yy), dz = _mm_sub_pd(pz, yz);
      const __m128d d = _mm_sqrt_pd(_mm_add_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)), _mm_mul_pd(dz, dz)));
      alignas(16) double dv[2], qx[2], qy[2], qz[2], w[2];
      _mm_store_pd(dv, d);
      _mm_store_pd(qx, _mm_div_pd(px, d));
      _mm_store_pd(qy, _mm_div_pd(py, d));
      _mm_store_pd(qz, _mm_div_pd(pz, d));
      _mm_store_pd(w, _mm_div_pd(one, d));
      pull(dv[0], qx[0], qy[0], qz[0], w[0]);
      pull(dv[1], qx[1], qy[1], qz[1], w[1]);
    }
#endif
    for (; i < n; ++i) {
      const Eigen::Vector3d& p = get(i);
      const double d = (p - y).norm();
      pull(d, p.x() / d, p.y() / d, p.z() / d, 1.0 / d);
    }
    if (weight_sum == 0.0) break;  // every point sits on y
    const Eigen::Vector3d t = weighted / weight_sum;
    Eigen::Vector3d next = t;
    if (coincident > 0) {  // Vardi & Zhang (2000): leave a data point only if the pull exceeds its mass
      const Eigen::Vector3d pull = (t - y) * weight_sum;
      const double r = pull.norm();
      const double eta = static_cast<double>(coincident);
      if (r <= eta) break;  // y is the median
      next = (1.0 - eta / r) * t + (eta / r) * y;
    }
    const double step = (next - y).norm();
    y = next;
    if (step < stop) break;
  }
  return y;
}

}  // namespace

Eigen::Vector3d l1_median(const std::vector<Eigen::Vector3d>& positions, const std::uint32_t* first,
                          const std::uint32_t* last, const L1MedianOptions& options) {
  const auto n = static_cast<std::size_t>(last - first);
  return weiszfeld(n, [&](std::size_t i) -> const Eigen::Vector3d& { return positions[first[i]]; }, options);
}

Eigen::Vector3d l1_median(const std::vector<Eigen::Vector3d>& points, const L1MedianOptions& options) {
  return weiszfeld(points.size(), [&](std::size_t i) -> const Eigen::Vector3d& { return points[i]; }, options);
}

}  // namespace treeskel
