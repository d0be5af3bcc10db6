#include "treeskel/l1_median.h"

#include <algorithm>
#include <numeric>

namespace treeskel {

namespace {

template <class Get>
Eigen::Vector3d weiszfeld(std::size_t count, Get get_all, const L1MedianOptions& options) {
  if (count == 0) return Eigen::Vector3d::Zero();
  const std::size_t stride =
      options.max_points > 0 && count > options.max_points ? (count + options.max_points - 1) / options.max_points : 1;
  const std::size_t n = (count + stride - 1) / stride;
  auto get = [&](std::size_t i) -> const Eigen::Vector3d& { return get_all(i * stride); };
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
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d& p = get(i);
      const double d = (p - y).norm();
      if (d <= coincide) {
        ++coincident;
        continue;
      }
      weighted += p / d;
      weight_sum += 1.0 / d;
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
