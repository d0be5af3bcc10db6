// Private to libskel: the point sets the L1-median and the CPC iterate over.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace treeskel::detail {

/// Copies `get_all(0)`, `get_all(stride)`, ... of a set of `count` points into `out`, the stride
/// thinning the set to about `max_points` (0: every point). The iterations then read contiguous
/// memory instead of following an index to a point of the cloud on every pass; the points and their
/// order are the same.
template <class Get>
void copy_thinned(std::size_t count, std::size_t max_points, Get get_all, std::vector<Eigen::Vector3d>& out) {
  const std::size_t stride = max_points > 0 && count > max_points ? (count + max_points - 1) / max_points : 1;
  out.resize((count + stride - 1) / stride);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = get_all(i * stride);
}

}  // namespace treeskel::detail
