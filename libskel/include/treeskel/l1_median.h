/// @file l1_median.h
/// The L1-median (geometric median) of a point set by Weiszfeld's iteration with the Vardi-Zhang
/// correction for iterates that land on a data point. Fu et al. 2020, eq. 2.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace treeskel {

struct L1MedianOptions {
  int max_iterations = 64;     ///< Weiszfeld steps at most
  double tolerance = 1e-4;     ///< stop when a step is shorter than this times the points' extent
  /// Larger sets are thinned to about this many points, taken at an even stride, before iterating:
  /// the median of a few thousand points of a branch slice is as good and keeps the cost bounded.
  std::size_t max_points = 4096;
};

/// L1-median of `positions[i]` for `i` in [first, last). Returns the origin for an empty range.
/// Deterministic: the same inputs give the same bits.
Eigen::Vector3d l1_median(const std::vector<Eigen::Vector3d>& positions, const std::uint32_t* first,
                          const std::uint32_t* last, const L1MedianOptions& options = {});

/// L1-median of all `points`.
Eigen::Vector3d l1_median(const std::vector<Eigen::Vector3d>& points, const L1MedianOptions& options = {});

}  // namespace treeskel
