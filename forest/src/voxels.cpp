#include "voxels.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <array>

namespace treeskel::forest::detail {

Voxels make_voxels(const PointCloud& cloud, const std::vector<std::uint8_t>& take, double voxel, const Eigen::Vector3d& low) {
  Voxels v;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;
  keyed.reserve(cloud.size());
  for (std::size_t p = 0; p < cloud.size(); ++p) {
    if (!take.empty() && !take[p]) continue;
    const Eigen::Vector3d g = ((cloud.positions[p] - low) / voxel).array().floor();
    keyed.emplace_back(pack(g.cast<int>()), static_cast<std::uint32_t>(p));
  }
  tbb::parallel_sort(keyed.begin(), keyed.end());
  v.of_point.assign(cloud.size(), Voxels::npos);
  v.members.reserve(keyed.size());
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    if (i == 0 || keyed[i].first != keyed[i - 1].first) {
      v.keys.push_back(keyed[i].first);
      v.first.push_back(static_cast<std::uint32_t>(i));
    }
    v.members.push_back(keyed[i].second);
    v.of_point[keyed[i].second] = static_cast<std::uint32_t>(v.keys.size() - 1);
  }
  v.first.push_back(static_cast<std::uint32_t>(keyed.size()));
  return v;
}

CellGraph voxel_graph(const Voxels& v, double voxel) {
  const std::size_t n = v.size();
  std::vector<std::array<std::int64_t, 26>> near(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t c) {
    const Eigen::Vector3i g = unpack(v.keys[c]);
    int k = 0;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if (dx == 0 && dy == 0 && dz == 0) continue;
          const Eigen::Vector3i h = g + Eigen::Vector3i(dx, dy, dz);
          near[c][k++] = (h.array() < 0).any() || (h.array() > static_cast<int>(kMask)).any() ? -1 : v.find(pack(h));
        }
  });
  CellGraph graph;
  graph.offsets.assign(n + 1, 0);
  for (std::size_t c = 0; c < n; ++c)
    graph.offsets[c + 1] = graph.offsets[c] + static_cast<std::uint32_t>(std::count_if(near[c].begin(), near[c].end(), [](std::int64_t t) { return t >= 0; }));
  graph.targets.resize(graph.offsets[n]);
  graph.weights.resize(graph.offsets[n]);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t c) {
    std::uint32_t at = graph.offsets[c];
    const Eigen::Vector3i g = unpack(v.keys[c]);
    for (std::int64_t t : near[c]) {
      if (t < 0) continue;
      graph.targets[at] = static_cast<std::uint32_t>(t);
      graph.weights[at] = voxel * (unpack(v.keys[t]) - g).cast<double>().norm();
      ++at;
    }
  });
  return graph;
}

}  // namespace treeskel::forest::detail
