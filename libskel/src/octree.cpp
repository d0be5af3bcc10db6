#include "treeskel/octree.h"

#include "treeskel/error.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

namespace treeskel {

namespace {

std::uint64_t spread_bits(std::uint32_t v) {
  std::uint64_t x = v & 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

std::uint32_t compact_bits(std::uint64_t x) {
  x &= 0x1249249249249249ULL;
  x = (x ^ (x >> 2)) & 0x10c30c30c30c30c3ULL;
  x = (x ^ (x >> 4)) & 0x100f00f00f00f00fULL;
  x = (x ^ (x >> 8)) & 0x1f0000ff0000ffULL;
  x = (x ^ (x >> 16)) & 0x1f00000000ffffULL;
  x = (x ^ (x >> 32)) & 0x1fffffULL;
  return static_cast<std::uint32_t>(x);
}

/// Sorts (key, index) pairs whose keys have `bits` bits: dealt by their top 12 bits into buckets (in
/// two halves at once), then the buckets sorted side by side. A bucket holding much of the cloud is
/// sorted in parallel itself. The same order as one sort of the pairs, in about two thirds of
/// tbb::parallel_sort's time at a million points.
void sort_keyed(std::vector<std::pair<std::uint64_t, std::uint32_t>>& keyed, int bits) {
  const std::size_t n = keyed.size();
  if (n < 65536) {
    std::sort(keyed.begin(), keyed.end());
    return;
  }
  constexpr int kTop = 12;
  constexpr std::size_t kBuckets = std::size_t{1} << kTop;
  const int shift = bits - kTop;
  const std::size_t bounds[3] = {0, n / 2, n};  // half t is keyed[bounds[t] .. bounds[t + 1])
  std::vector<std::size_t> count[2] = {std::vector<std::size_t>(kBuckets, 0), std::vector<std::size_t>(kBuckets, 0)};
  tbb::parallel_for(0, 2, [&](int t) {
    auto& c = count[t];
    for (std::size_t i = bounds[t]; i < bounds[t + 1]; ++i) ++c[keyed[i].first >> shift];
  });
  std::vector<std::size_t> start(kBuckets + 1);
  std::size_t sum = 0;
  for (std::size_t b = 0; b < kBuckets; ++b) {
    start[b] = sum;
    const std::size_t first = count[0][b], second = count[1][b];
    count[0][b] = sum;
    count[1][b] = sum + first;
    sum += first + second;
  }
  start[kBuckets] = n;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> dealt(n);
  tbb::parallel_for(0, 2, [&](int t) {
    auto& next = count[t];
    for (std::size_t i = bounds[t]; i < bounds[t + 1]; ++i) dealt[next[keyed[i].first >> shift]++] = keyed[i];
  });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, kBuckets, 1), [&](const auto& range) {
    for (std::size_t b = range.begin(); b != range.end(); ++b) {
      const auto first = dealt.begin() + static_cast<std::ptrdiff_t>(start[b]);
      const auto last = dealt.begin() + static_cast<std::ptrdiff_t>(start[b + 1]);
      if (start[b + 1] - start[b] > n / 8) tbb::parallel_sort(first, last);
      else std::sort(first, last);
    }
  });
  keyed.swap(dealt);
}

}  // namespace

std::uint64_t morton_encode(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  return spread_bits(x) | spread_bits(y) << 1 | spread_bits(z) << 2;
}

Eigen::Vector3i morton_decode(std::uint64_t key) {
  return {static_cast<int>(compact_bits(key)), static_cast<int>(compact_bits(key >> 1)),
          static_cast<int>(compact_bits(key >> 2))};
}

int paper_octree_depth(std::size_t point_count) {
  if (point_count < 2) return 1;
  const double d = 2.0 + std::log(static_cast<double>(point_count)) / std::log(8.0);
  return std::clamp(static_cast<int>(std::floor(d + 1e-9)), 1, 21);
}

Eigen::Vector3i OctreeCells::coordinates(std::size_t cell) const { return morton_decode(keys[cell]); }

std::int64_t OctreeCells::find(const Eigen::Vector3i& c) const {
  const int n = 1 << depth;
  if ((c.array() < 0).any() || (c.array() >= n).any()) return -1;
  const auto key = morton_encode(c.x(), c.y(), c.z());
  const auto it = std::lower_bound(keys.begin(), keys.end(), key);
  if (it == keys.end() || *it != key) return -1;
  return it - keys.begin();
}

OctreeCells partition_octree(const PointCloud& cloud, const OctreeOptions& options) {
  if (cloud.empty()) throw InputError("the point cloud is empty");
  if (options.depth < 0 || options.depth > 21)
    throw OptionError("octree depth must be between 1 and 21 (0 for the default), got " + std::to_string(options.depth));
  OctreeCells cells;
  // Points far outside the cloud's bulk are left out, and the cube bounds the others.
  std::vector<std::uint32_t> kept;
  Eigen::AlignedBox3d box = bounding_box(cloud);
  if (options.outlier_distance > 0.0 && cloud.size() >= 1000) {
    // Per axis, the values of ranks 0.1% and 99.9% of the way: the heaviest of the smallest ones and
    // the lightest of the largest ones, kept in two heaps in one pass (most values pass by both
    // heaps' tops; six selections over copies of the whole cloud took 0.08 s at 1M points).
    Eigen::AlignedBox3d bulk;
    const std::size_t n = cloud.size();
    const auto low = static_cast<std::size_t>(0.001 * static_cast<double>(n - 1));
    const auto high = static_cast<std::size_t>(0.999 * static_cast<double>(n - 1));
    // Keeps in `heap` the `size` values that come first by `before`; its top is the last of them.
    const auto keep = [](std::vector<double>& heap, std::size_t size, double v, auto before) {
      if (heap.size() < size) {
        heap.push_back(v);
        std::push_heap(heap.begin(), heap.end(), before);
      } else if (before(v, heap.front())) {
        std::pop_heap(heap.begin(), heap.end(), before);
        heap.back() = v;
        std::push_heap(heap.begin(), heap.end(), before);
      }
    };
    tbb::parallel_for(0, 3, [&](int a) {
      std::vector<double> smallest, largest;  // a max-heap of low + 1 values, a min-heap of n - high
      smallest.reserve(low + 1);
      largest.reserve(n - high);
      for (std::size_t i = 0; i < n; ++i) {
        const double v = cloud.positions[i][a];
        keep(smallest, low + 1, v, std::less<double>());
        keep(largest, n - high, v, std::greater<double>());
      }
      bulk.min()[a] = smallest.front();
      bulk.max()[a] = largest.front();
    });
    const double reach = options.outlier_distance * bulk.sizes().maxCoeff();
    bulk.min().array() -= reach;
    bulk.max().array() += reach;
    if (!bulk.contains(box)) {
      box.setEmpty();
      for (std::size_t i = 0; i < cloud.size(); ++i) {
        if (bulk.contains(cloud.positions[i])) {
          kept.push_back(static_cast<std::uint32_t>(i));
          box.extend(cloud.positions[i]);
        } else {
          cells.outliers.push_back(static_cast<std::uint32_t>(i));
        }
      }
    }
  }
  const bool all = kept.empty();  // no outlier: every point, by its own index
  cells.origin = box.min();
  cells.cube_size = std::max(box.sizes().maxCoeff(), 1e-300);

  // Morton keys at the finest depth, sorted once: the cells of any coarser depth are runs of keys that
  // share a prefix, so every depth can be counted from this one sort.
  constexpr int finest = 21;
  const std::size_t n = all ? cloud.size() : kept.size();
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(n);
  const double resolution = static_cast<double>(1u << finest);
  // For each point, the shallowest depth at which it lies in another cell than the point before it:
  // 21 - (its highest bit that differs) / 3, and 22 for a repeat (the same finest key), which no
  // depth tells apart. A cell at depth d starts at every point whose split is at most d.
  constexpr std::uint8_t kRepeat = finest + 1;
  std::vector<std::uint8_t> split(n);
  const auto sort_points = [&](double cube_size) {
    const double inv = resolution / cube_size;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const auto& range) {
      for (std::size_t j = range.begin(); j != range.end(); ++j) {
        const std::uint32_t i = all ? static_cast<std::uint32_t>(j) : kept[j];
        const Eigen::Vector3d g = (cloud.positions[i] - cells.origin) * inv;
        std::uint32_t c[3];
        for (int a = 0; a < 3; ++a) c[a] = static_cast<std::uint32_t>(std::clamp(std::floor(g[a]), 0.0, resolution - 1.0));
        keyed[j] = {morton_encode(c[0], c[1], c[2]), i};
      }
    });
    sort_keyed(keyed, 3 * finest);  // keys with indices are unique: deterministic
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 8192), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        if (i == 0) {
          split[i] = 0;
          continue;
        }
        const std::uint64_t differ = keyed[i].first ^ keyed[i - 1].first;
        split[i] = differ == 0 ? kRepeat : static_cast<std::uint8_t>(finest - (63 - __builtin_clzll(differ)) / 3);
      }
    });
  };
  // The deepest depth up to `deepest` at which the cell of a typical point (the point-weighted median
  // of the cell counts) holds `points_per_cell`: unlike the mean, it ignores stray outliers that sit
  // alone in their cells. It reaches the target exactly when fewer than half the points lie in cells
  // below the target: counted per depth in one pass, with no list of cells to sort.
  const auto dense_depth = [&](int deepest, std::size_t distinct) {
    int depth = 1;
    std::vector<std::size_t> below(static_cast<std::size_t>(deepest) + 1, 0);  // points in cells under the target, per depth
    if (options.points_per_cell <= 1.0) {
      // No cell holds fewer than one point.
    } else if (options.points_per_cell <= 2.0) {
      // Cells under the target hold one point: a point is alone in its cell from the depth at which
      // both it and the next distinct point start a cell, so one pass counts every depth.
      std::vector<std::size_t> alone_from(kRepeat + 1, 0);
      std::size_t previous = n;  // the last distinct point seen
      for (std::size_t i = 0; i < n; ++i) {
        if (split[i] == kRepeat) continue;
        if (previous != n) ++alone_from[std::max(split[previous], split[i])];
        previous = i;
      }
      if (previous != n) ++alone_from[split[previous]];
      std::size_t sum = 0;
      for (int d = 0; d <= deepest; ++d) {
        sum += alone_from[static_cast<std::size_t>(d)];
        below[static_cast<std::size_t>(d)] = sum;
      }
    } else {
      const auto sparse = [&](std::size_t run) { return static_cast<double>(run) < options.points_per_cell; };
      for (int d = 1; d <= deepest; ++d) {
        std::size_t run = 0;
        auto& count = below[static_cast<std::size_t>(d)];
        for (std::size_t i = 0; i < n; ++i) {
          if (split[i] == kRepeat) continue;  // a repeated point
          if (i > 0 && split[i] <= d) {
            if (sparse(run)) count += run;
            run = 0;
          }
          ++run;
        }
        if (sparse(run)) count += run;
      }
    }
    for (int d = 1; d <= deepest; ++d)
      if (2 * below[static_cast<std::size_t>(d)] < distinct) depth = d;
    return depth;
  };
  if (options.depth > 0) {
    if (!(options.cube_scale >= 1.0 && options.cube_scale <= 2.0))
      throw OptionError("the octree's cube scale must be between 1 and 2, got " + std::to_string(options.cube_scale));
    cells.cube_scale = options.cube_scale;
    cells.cube_size *= options.cube_scale;
  }
  sort_points(cells.cube_size);
  if (options.depth > 0) {
    cells.depth = options.depth;
  } else {
    // Repeated points (the same finest key) count once: duplicating a cloud changes nothing.
    const std::size_t distinct = static_cast<std::size_t>(std::count_if(split.begin(), split.end(), [](std::uint8_t v) { return v != kRepeat; }));
    const int paper = paper_octree_depth(distinct);
    cells.depth = paper;
    if (options.points_per_cell > 0.0) {
      cells.depth = dense_depth(std::min(finest, paper + std::max(0, options.max_extra_depth)), distinct);
      const int steps = distinct <= options.depth_steps_max_points ? options.depth_steps : 1;
      if (steps > 1) {
        // Cells of sizes between those of two depths: the cube grown by 2^(k / steps), whose depths
        // may hold the target at a cell finer than the plain cube's. The finest cell wins, at most
        // as fine as 2^-(2 + log8 N + max_extra_depth) of the plain cube (the depth cap, unrounded:
        // at k = 0 it is the cap above).
        const double limit = 2.0 + std::log2(static_cast<double>(std::max<std::size_t>(distinct, 2))) / 3.0 +
                             std::max(0, options.max_extra_depth);
        double best_cell = cells.cube_size / static_cast<double>(1u << cells.depth);
        double best_scale = 1.0;
        int best_depth = cells.depth;
        const double plain = cells.cube_size;
        double sorted = 1.0;  // the scale of the cube the keys are of
        for (int k = 1; k < steps; ++k) {
          const double grow = static_cast<double>(k) / steps;
          // The scale as a 32-bit float holds it, so that one passed on through a float (MeshLab's
          // parameters) pins the very same cube.
          const double scale = static_cast<double>(static_cast<float>(std::exp2(grow)));
          const int deepest = std::min(finest, static_cast<int>(std::floor(limit + grow + 1e-9)));
          if (plain * scale / static_cast<double>(1u << deepest) >= best_cell) continue;  // cannot be finer
          sort_points(plain * scale);
          sorted = scale;
          const int d = dense_depth(deepest, distinct);
          const double cell = plain * scale / static_cast<double>(1u << d);
          if (cell < best_cell) {
            best_cell = cell;
            best_scale = scale;
            best_depth = d;
          }
        }
        cells.depth = best_depth;
        cells.cube_scale = best_scale;
        cells.cube_size = plain * best_scale;
        // The keys of the chosen cube (the last one sorted may be another).
        if (sorted != best_scale) sort_points(cells.cube_size);
      }
    }
  }
  cells.cell_size = cells.cube_size / static_cast<double>(1u << cells.depth);
  const int shift = 3 * (finest - cells.depth);

  cells.point_order.resize(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 8192), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) cells.point_order[i] = keyed[i].second;
  });
  const auto starts = [&](std::size_t i) { return i == 0 || split[i] <= cells.depth; };
  std::size_t cell_count = 0;
  for (std::size_t i = 0; i < n; ++i) cell_count += starts(i);
  cells.keys.reserve(cell_count);
  cells.first.reserve(cell_count + 1);
  for (std::size_t i = 0; i < n; ++i)
    if (starts(i)) {
      cells.keys.push_back(keyed[i].first >> shift);
      cells.first.push_back(static_cast<std::uint32_t>(i));
    }
  cells.first.push_back(static_cast<std::uint32_t>(n));

  // Points at the very same place share their finest key, so they sit in one run of repeated keys, in
  // index order: each point of a run is compared with the first point of every place seen before it
  // in the run (runs are short: a few points share a place, or many points one place).
  std::vector<std::uint32_t> places;
  for (std::size_t i = 1; i < n; ++i) {
    if (split[i] != kRepeat) continue;
    if (split[i - 1] != kRepeat) places.assign(1, keyed[i - 1].second);
    const std::uint32_t p = keyed[i].second;
    const auto same = std::find_if(places.begin(), places.end(),
                                   [&](std::uint32_t f) { return cloud.positions[f] == cloud.positions[p]; });
    if (same != places.end()) cells.repeats.emplace_back(p, *same);
    else places.push_back(p);
  }
  // The outliers, which have no key: sorted by place, then index.
  std::vector<std::uint32_t> stray = cells.outliers;
  const auto before = [&](std::uint32_t a, std::uint32_t b) {
    const Eigen::Vector3d& p = cloud.positions[a];
    const Eigen::Vector3d& q = cloud.positions[b];
    for (int k = 0; k < 3; ++k)
      if (p[k] != q[k]) return p[k] < q[k];
    return a < b;
  };
  std::sort(stray.begin(), stray.end(), before);
  for (std::size_t i = 1, f = 0; i < stray.size(); ++i) {
    if (cloud.positions[stray[i]] != cloud.positions[stray[f]]) f = i;
    else cells.repeats.emplace_back(stray[i], stray[f]);
  }
  std::sort(cells.repeats.begin(), cells.repeats.end());
  return cells;
}

void compute_cell_medians(OctreeCells& cells, const PointCloud& cloud, const L1MedianOptions& options) {
  cells.medians.resize(cells.cell_count());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.cell_count(), 256), [&](const auto& range) {
    for (std::size_t c = range.begin(); c != range.end(); ++c)
      cells.medians[c] = l1_median(cloud.positions, cells.begin(c), cells.end(c), options);
  });
}

OctreeCells build_octree_cells(const PointCloud& cloud, const OctreeOptions& options) {
  OctreeCells cells = partition_octree(cloud, options);
  compute_cell_medians(cells, cloud, options.median);
  return cells;
}

}  // namespace treeskel
