#include "treeskel/forest/segment.h"

#include "voxels.h"

#include "treeskel/error.h"
#include "treeskel/geodesic.h"
#include "treeskel/kd_search.h"
#include "treeskel/neighbour_graph.h"


#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>

namespace treeskel::forest {

namespace {

using detail::kMask;
using detail::Voxels;
using detail::make_voxels;
using detail::voxel_graph;

using kd::Point;
using kd::PointMap;
using kd::Traits;
using Nearest = kd::KnnSearch;
using KdTree = kd::Tree;

/// The stems by plan cells at least as wide as the widest stem's circle plus the margin, to find the
/// stem whose circle (plus the margin) holds a point without trying every stem.
class StemIndex {
public:
  StemIndex(const std::vector<Stem>& stems, double margin) : stems_(stems), margin_(margin) {
    for (const auto& st : stems) cell_ = std::max(cell_, st.radius + margin);
    for (std::size_t t = 0; t < stems.size(); ++t)
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          cells_[key(stems[t].centre + cell_ * Eigen::Vector2d(dx, dy))].push_back(static_cast<std::uint32_t>(t));
  }

  /// The nearest stem whose circle plus the margin holds `at` in plan, as (1 + its index, distance
  /// to its centre); (0, infinity) when none does.
  std::pair<std::uint32_t, double> holding(const Eigen::Vector2d& at) const {
    std::pair<std::uint32_t, double> best{0, std::numeric_limits<double>::infinity()};
    const auto it = cells_.find(key(at));
    if (it == cells_.end()) return best;
    for (std::uint32_t t : it->second) {
      const double d = (at - stems_[t].centre).norm();
      if (d <= stems_[t].radius + margin_ && d < best.second) best = {t + 1, d};
    }
    return best;
  }

private:
  std::uint64_t key(const Eigen::Vector2d& at) const {
    const auto i = static_cast<std::int32_t>(std::floor(at.x() / cell_));
    const auto j = static_cast<std::int32_t>(std::floor(at.y() / cell_));
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(i)) << 32) | static_cast<std::uint32_t>(j);
  }

  const std::vector<Stem>& stems_;
  double margin_;
  double cell_ = 0.5;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
};

}  // namespace

Segmentation segment_trees(const PointCloud& cloud, const Ground& ground, const std::vector<Stem>& stems,
                           const StemOptions& stem_options, const SegmentOptions& o) {
  if (!(o.voxel > 0) || !(o.seed_margin >= 0) || !(o.max_gap >= 0))
    throw OptionError("segmentation: the voxel must be positive, the margin and the gap not negative");
  TREESKEL_REQUIRE(ground.height.size() == cloud.size() && ground.is_ground.size() == cloud.size(), "ground of another cloud");
  Segmentation s;
  s.tree.assign(cloud.size(), 0);
  if (cloud.size() == ground.ground_points) return s;
  const Eigen::Vector3d low = bounding_box(cloud).min();
  if (((bounding_box(cloud).sizes() / o.voxel).array() >= static_cast<double>(kMask)).any())
    throw InputError("the plot is too large for voxels of " + std::to_string(o.voxel) + " (is it in metres?)");
  std::vector<std::uint8_t> off_ground(cloud.size());
  for (std::size_t p = 0; p < cloud.size(); ++p) off_ground[p] = !ground.is_ground[p];
  const Voxels v = make_voxels(cloud, off_ground, o.voxel, low);
  s.voxels = v.size();
  const CellGraph graph = voxel_graph(v, o.voxel);

  // Seeds: the voxels of each stem's trunk, up to the slice's top; a voxel two stems claim goes to the
  // nearer centre.
  const StemIndex stem_index(stems, o.seed_margin);
  std::vector<std::uint32_t> label(v.size(), 0);
  std::vector<double> seed_distance(v.size(), std::numeric_limits<double>::infinity());
  for (std::size_t vi = 0; vi < v.size(); ++vi)
    for (std::uint32_t m = v.first[vi]; m < v.first[vi + 1]; ++m) {
      const std::uint32_t p = v.members[m];
      if (ground.height[p] > stem_options.slice_top) continue;
      const auto [stem, d] = stem_index.holding(cloud.positions[p].head<2>());
      if (stem && d < seed_distance[vi]) {
        seed_distance[vi] = d;
        label[vi] = stem;
      }
    }
  std::vector<std::uint32_t> sources;
  for (std::size_t vi = 0; vi < v.size(); ++vi)
    if (label[vi]) sources.push_back(static_cast<std::uint32_t>(vi));

  if (!sources.empty()) {
    const GeodesicField field = geodesic_distance(graph, sources);
    std::vector<std::uint32_t> order;
    for (std::size_t vi = 0; vi < v.size(); ++vi)
      if (std::isfinite(field.distance[vi]) && !label[vi]) order.push_back(static_cast<std::uint32_t>(vi));
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
      return field.distance[a] != field.distance[b] ? field.distance[a] < field.distance[b] : a < b;
    });
    for (std::uint32_t vi : order) label[vi] = label[static_cast<std::size_t>(field.predecessor[vi])];
  }

  // Parts no path joins to a stem: to the nearest tree when close and tall enough.
  std::uint32_t parts = 0;
  const std::vector<std::uint32_t> part = connected_components(graph, &parts);
  std::vector<double> part_top(parts, -std::numeric_limits<double>::infinity());
  std::vector<char> part_reached(parts, 0);
  for (std::size_t vi = 0; vi < v.size(); ++vi) {
    part_reached[part[vi]] |= label[vi] != 0;
    for (std::uint32_t m = v.first[vi]; m < v.first[vi + 1]; ++m)
      part_top[part[vi]] = std::max(part_top[part[vi]], static_cast<double>(ground.height[v.members[m]]));
  }
  // Rounds: the parts within reach of the trees as they stand join them, then the parts within reach
  // of those, until none joins (a sparse crown's parts hang off each other, not all off the trunk).
  std::vector<char> pending(parts, 0);
  for (std::uint32_t c = 0; c < parts; ++c) pending[c] = !part_reached[c] && part_top[c] >= o.understorey;
  auto centre_of = [&](std::size_t vi) {
    const Eigen::Vector3d c = v.centre(vi, o.voxel);
    return Point(c.x(), c.y(), c.z());
  };
  while (std::find(pending.begin(), pending.end(), 1) != pending.end()) {
    std::vector<Point> centres;
    std::vector<std::uint32_t> labelled;
    for (std::size_t vi = 0; vi < v.size(); ++vi)
      if (label[vi]) {
        centres.push_back(centre_of(vi));
        labelled.push_back(static_cast<std::uint32_t>(vi));
      }
    if (labelled.empty()) break;
    std::vector<std::uint32_t> ids(centres.size());
    std::iota(ids.begin(), ids.end(), 0u);
    const PointMap map(centres.data());
    KdTree tree(ids.begin(), ids.end(), KdTree::Splitter(), Traits(map));
    tree.build();
    std::vector<std::pair<double, std::uint32_t>> nearest(v.size(), {std::numeric_limits<double>::infinity(), 0});
    tbb::parallel_for(std::size_t{0}, v.size(), [&](std::size_t vi) {
      if (label[vi] || !pending[part[vi]]) return;
      Nearest search(tree, centre_of(vi), 1, 0, true, Nearest::Distance(map));
      const auto it = search.begin();
      if (it != search.end()) nearest[vi] = {std::sqrt(it->second), label[labelled[it->first]]};
    });
    std::vector<double> best(parts, std::numeric_limits<double>::infinity());
    std::vector<std::uint32_t> best_label(parts, 0);
    for (std::size_t vi = 0; vi < v.size(); ++vi)
      if (nearest[vi].first < best[part[vi]] ||
          (nearest[vi].first == best[part[vi]] && nearest[vi].second < best_label[part[vi]])) {
        best[part[vi]] = nearest[vi].first;
        best_label[part[vi]] = nearest[vi].second;
      }
    bool joined = false;
    for (std::uint32_t c = 0; c < parts; ++c)
      if (pending[c] && best[c] <= o.max_gap) {
        pending[c] = 0;
        joined = true;
      }
    if (!joined) break;
    for (std::size_t vi = 0; vi < v.size(); ++vi)
      if (!label[vi] && !pending[part[vi]] && best[part[vi]] <= o.max_gap) label[vi] = best_label[part[vi]];
  }
  for (std::size_t vi = 0; vi < v.size(); ++vi) s.unreached_voxels += !label[vi];
  for (std::size_t p = 0; p < cloud.size(); ++p) {
    if (v.of_point[p] == Voxels::npos) continue;
    s.tree[p] = label[v.of_point[p]];
    s.unassigned_points += s.tree[p] == 0;
  }
  // The ground's points inside a stem's circle are its base: the tree then reaches the ground, and
  // its height and breast height are measured from there.
  for (std::size_t p = 0; p < cloud.size(); ++p) {
    if (!ground.is_ground[p]) continue;
    s.tree[p] = stem_index.holding(cloud.positions[p].head<2>()).first;
    s.stem_base_points += s.tree[p] != 0;
  }
  return s;
}

std::vector<TreeShape> describe_trees(const PointCloud& cloud, const std::vector<Stem>& stems,
                                      const Segmentation& seg, const StemOptions& stem_options) {
  constexpr double kLayer = 0.25;
  constexpr double kSpreadShare = 0.1;
  std::vector<TreeShape> shapes(stems.size());
  std::vector<std::vector<std::pair<int, bool>>> layers(stems.size());  // (layer, spread) per point
  for (std::size_t p = 0; p < cloud.size(); ++p) {
    const std::uint32_t t = seg.tree[p];
    if (t == 0) continue;
    TreeShape& s = shapes[t - 1];
    const Stem& stem = stems[t - 1];
    const Eigen::Vector3d& q = cloud.positions[p];
    if (s.points == 0) s.low = s.high = q;
    s.low = s.low.cwiseMin(q);
    s.high = s.high.cwiseMax(q);
    ++s.points;
    const double h = q.z() - stem.ground;
    s.height = std::max(s.height, h);
    if (h < stem_options.slice_bottom) continue;
    const bool spread = (q.head<2>() - stem.centre).norm() > std::max(1.0, 4.0 * stem.radius);
    layers[t - 1].emplace_back(static_cast<int>((h - stem_options.slice_bottom) / kLayer), spread);
  }
  for (std::size_t t = 0; t < stems.size(); ++t) {
    TreeShape& s = shapes[t];
    s.crown_base = s.height;
    std::vector<std::pair<int, bool>>& l = layers[t];
    std::sort(l.begin(), l.end());
    for (std::size_t i = 0; i < l.size();) {
      std::size_t j = i, spread = 0;
      while (j < l.size() && l[j].first == l[i].first) spread += l[j++].second;
      if (static_cast<double>(spread) >= kSpreadShare * static_cast<double>(j - i) && j - i >= 10) {
        s.crown_base = stem_options.slice_bottom + l[i].first * kLayer;
        break;
      }
      i = j;
    }
  }
  return shapes;
}

}  // namespace treeskel::forest
