// Voxels of a cloud and the graph joining each to its 26 neighbours (internal to forest/).
#pragma once

#include "treeskel/neighbour_graph.h"
#include "treeskel/point_cloud.h"

#include <Eigen/Core>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

namespace treeskel::forest::detail {

constexpr int kBits = 21;  // per axis of a voxel key
constexpr std::uint64_t kMask = (std::uint64_t{1} << kBits) - 1;

inline Eigen::Vector3i unpack(std::uint64_t key) {
  return {static_cast<int>(key & kMask), static_cast<int>((key >> kBits) & kMask), static_cast<int>(key >> (2 * kBits))};
}

inline std::uint64_t pack(const Eigen::Vector3i& g) {
  return static_cast<std::uint64_t>(g.x()) | (static_cast<std::uint64_t>(g.y()) << kBits) |
         (static_cast<std::uint64_t>(g.z()) << (2 * kBits));
}

/// The voxels of the points `take` keeps: sorted keys, each voxel's points, each point's voxel.
struct Voxels {
  std::vector<std::uint64_t> keys;           // sorted, one per voxel
  std::vector<std::uint32_t> first;          // voxel v holds members[first[v] .. first[v + 1])
  std::vector<std::uint32_t> members;        // point indices, by voxel
  std::vector<std::uint32_t> of_point;       // per point; npos for the points not taken
  static constexpr std::uint32_t npos = std::numeric_limits<std::uint32_t>::max();

  std::size_t size() const { return keys.size(); }
  std::int64_t find(std::uint64_t key) const {
    const auto it = std::lower_bound(keys.begin(), keys.end(), key);
    return it != keys.end() && *it == key ? it - keys.begin() : -1;
  }
  /// The voxel's centre, relative to the grid's low corner.
  Eigen::Vector3d centre(std::size_t v, double voxel) const { return (unpack(keys[v]).cast<double>().array() + 0.5) * voxel; }
};

/// The voxels (edge `voxel`, grid from `low`) of the points p with take[p] != 0 (all when `take` is empty).
Voxels make_voxels(const PointCloud& cloud, const std::vector<std::uint8_t>& take, double voxel, const Eigen::Vector3d& low);

/// Each voxel joined to the occupied ones of its 26 neighbours, at the distance between their centres.
CellGraph voxel_graph(const Voxels& v, double voxel);

}  // namespace treeskel::forest::detail
