#include "treeskel/octree.h"

#include "treeskel/error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace treeskel {
namespace {

/// The population of the cell a typical point lies in: the point-weighted median of the cells' counts.
double typical_population(const OctreeCells& cells) {
  std::vector<std::size_t> counts;
  for (std::size_t c = 0; c < cells.cell_count(); ++c) counts.push_back(cells.point_count(c));
  std::sort(counts.begin(), counts.end());
  std::size_t total = 0, seen = 0;
  for (auto n : counts) total += n;
  for (auto n : counts)
    if (2 * (seen += n) >= total) return static_cast<double>(n);
  return 0.0;
}

TEST(Octree, MortonRoundTrips) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<std::uint32_t> d(0, (1u << 21) - 1);
  for (int i = 0; i < 1000; ++i) {
    const std::uint32_t x = d(rng), y = d(rng), z = d(rng);
    EXPECT_EQ(morton_decode(morton_encode(x, y, z)), Eigen::Vector3i(int(x), int(y), int(z)));
  }
  EXPECT_EQ(morton_encode(1, 0, 0), 1u);
  EXPECT_EQ(morton_encode(0, 1, 0), 2u);
  EXPECT_EQ(morton_encode(0, 0, 1), 4u);
}

TEST(Octree, PaperDepthIsTwoPlusLog8) {
  EXPECT_EQ(paper_octree_depth(1), 1);
  EXPECT_EQ(paper_octree_depth(8), 3);
  EXPECT_EQ(paper_octree_depth(4096), 6);
  EXPECT_EQ(paper_octree_depth(1000000), 8);  // 2 + 6.64
  EXPECT_EQ(paper_octree_depth(14045), 6);    // 2 + 4.59
}

TEST(Octree, DefaultDepthFollowsThePointDensity) {
  // 20,000 points on a unit square: 4^d cells at depth d hold 20000 / 4^d points each.
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  PointCloud square;
  for (int i = 0; i < 20000; ++i) square.positions.emplace_back(u(rng), u(rng), 0.0);
  OctreeOptions three;
  three.points_per_cell = 3.0;
  three.depth_steps = 1;  // whole depths (grown cubes: GrownCubesGiveTheFinestCellThatHoldsTheTarget)
  const OctreeCells cells = build_octree_cells(square, three);
  EXPECT_EQ(cells.depth, 6);  // 20000 / 4096 = 4.9 points a cell; depth 7 would give 1.2
  EXPECT_GE(20000.0 / cells.cell_count(), 2.5);
  // The default asks for 2: at depth 7 the cell of a typical point (the point-weighted median of the
  // cell populations) holds 2, though the mean is 1.2.
  OctreeOptions whole;
  whole.depth_steps = 1;
  const OctreeCells fine = build_octree_cells(square, whole);
  EXPECT_EQ(fine.depth, 7);
  EXPECT_GE(typical_population(fine), OctreeOptions{}.points_per_cell);
  OctreeOptions paper;
  paper.points_per_cell = 0.0;
  EXPECT_EQ(build_octree_cells(square, paper).depth, paper_octree_depth(20000));
  OctreeOptions capped;
  capped.depth_steps = 1;
  capped.points_per_cell = 0.5;  // would go to depth 8 or more, but only 1 beyond the paper's 6
  EXPECT_EQ(build_octree_cells(square, capped).depth, 7);
}

TEST(Octree, DefaultDepthIsTheDeepestWhereFewerThanHalfThePointsLieInSmallerCells) {
  // The rule checked against the cells of every depth, built one by one: clumps of points of many
  // sizes, so that the depths differ in how many points lie in cells under the target.
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int trial = 0; trial < 6; ++trial) {
    PointCloud cloud;
    const int clumps = 5 + 20 * trial;
    for (int k = 0; k < clumps; ++k) {
      const Eigen::Vector3d centre(u(rng), u(rng), u(rng));
      const double spread = 0.002 * std::pow(10.0, 2.0 * u(rng));
      for (int i = 0, n = 1 + static_cast<int>(300 * u(rng)); i < n; ++i)
        cloud.positions.push_back(centre + spread * Eigen::Vector3d(g(rng), g(rng), g(rng)));
    }
    const std::size_t n = cloud.size();
    for (double target : {0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 5.0}) {
      OctreeOptions options;
      options.points_per_cell = target;
      options.max_extra_depth = 3;
      options.depth_steps = 1;
      const int deepest = std::min(21, paper_octree_depth(n) + options.max_extra_depth);
      int expected = 1;
      for (int d = 1; d <= deepest; ++d) {
        OctreeOptions fixed;
        fixed.depth = d;
        const OctreeCells cells = build_octree_cells(cloud, fixed);
        std::size_t below = 0;
        for (std::size_t c = 0; c < cells.cell_count(); ++c)
          if (static_cast<double>(cells.point_count(c)) < target) below += cells.point_count(c);
        if (2 * below < n) expected = d;
      }
      EXPECT_EQ(partition_octree(cloud, options).depth, expected) << "trial " << trial << ", target " << target;
    }
  }
}

TEST(Octree, GrownCubesGiveTheFinestCellThatHoldsTheTarget) {
  // The rule checked against cells built at every fixed depth and cube scale: a cube grown by
  // 2^(k/4) at depth d has cells of 2^(k/4 - d) of the plain cube; the finest whose typical point's
  // cell holds 2 points wins, under the cap 2 + log8 N + 1 levels taken unrounded.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const int count : {3000, 9000, 20000}) {
    PointCloud cloud;  // a unit square with a denser strip: the typical cell is not the mean one
    for (int i = 0; i < count; ++i) cloud.positions.emplace_back(u(rng), i % 3 == 0 ? 0.2 * u(rng) : u(rng), 0.0);
    const OctreeOptions defaults;
    ASSERT_EQ(defaults.depth_steps, 4);
    const double limit = 2.0 + std::log2(static_cast<double>(count)) / 3.0 + defaults.max_extra_depth;
    double expected = 2.0;  // the plain cube's side is 1
    double expected_scale = 1.0;
    for (int k = 0; k < 4; ++k)
      for (int d = 1; d <= static_cast<int>(std::floor(limit + k / 4.0)); ++d) {
        OctreeOptions fixed;
        fixed.depth = d;
        fixed.cube_scale = static_cast<float>(std::exp2(k / 4.0));  // as the octree rounds it
        const OctreeCells cells = partition_octree(cloud, fixed);
        const double cell = cells.cell_size;
        if (typical_population(cells) >= defaults.points_per_cell && cell < expected) {
          expected = cell;
          expected_scale = fixed.cube_scale;
        }
      }
    const OctreeCells chosen = build_octree_cells(cloud, defaults);
    const double side = (bounding_box(cloud).sizes()).maxCoeff();
    EXPECT_NEAR(chosen.cell_size / side, expected / side, 1e-12) << count << " points";
    EXPECT_DOUBLE_EQ(chosen.cube_scale, expected_scale) << count << " points";
    EXPECT_GE(typical_population(chosen), defaults.points_per_cell);
    // Never coarser than the whole depths give.
    OctreeOptions whole;
    whole.depth_steps = 1;
    const OctreeCells plain = partition_octree(cloud, whole);
    EXPECT_LE(chosen.cell_size, plain.cell_size);
    EXPECT_EQ(plain.cube_scale, 1.0);
    // The depth and scale pinned give the very same cells (what automatic_options relies on).
    OctreeOptions pinned;
    pinned.depth = chosen.depth;
    pinned.cube_scale = chosen.cube_scale;
    const OctreeCells again = partition_octree(cloud, pinned);
    EXPECT_EQ(again.keys, chosen.keys);
    EXPECT_EQ(again.point_order, chosen.point_order);
    // Above the point limit, whole depths only.
    OctreeOptions limited;
    limited.depth_steps_max_points = static_cast<std::size_t>(count) - 1;
    EXPECT_EQ(partition_octree(cloud, limited).cell_size, plain.cell_size);
  }
  // At least one of the clouds takes a grown cube, or the test shows nothing.
  PointCloud square;
  for (int i = 0; i < 20000; ++i) square.positions.emplace_back(u(rng), u(rng), 0.0);
  EXPECT_GT(partition_octree(square, {}).cube_scale, 1.0);
  OctreeOptions wrong;
  wrong.depth = 5;
  wrong.cube_scale = 0.5;
  EXPECT_THROW(partition_octree(square, wrong), OptionError);
}

TEST(Octree, EveryPointIsInExactlyOneCellThatContainsIt) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 3.0);
  PointCloud cloud;
  for (int i = 0; i < 5000; ++i) cloud.positions.emplace_back(u(rng), u(rng) * 0.5, u(rng) * 0.2);
  const OctreeCells cells = build_octree_cells(cloud, {});
  EXPECT_GE(typical_population(cells), OctreeOptions{}.points_per_cell);
  std::vector<int> seen(cloud.size(), 0);
  for (std::size_t c = 0; c < cells.cell_count(); ++c) {
    EXPECT_GT(cells.point_count(c), 0u);
    if (c > 0) {
      EXPECT_LT(cells.keys[c - 1], cells.keys[c]);
    }
    const Eigen::Vector3d lo = cells.origin + cells.coordinates(c).cast<double>() * cells.cell_size;
    const Eigen::AlignedBox3d box(lo, lo + Eigen::Vector3d::Constant(cells.cell_size));
    for (auto it = cells.begin(c); it != cells.end(c); ++it) {
      ++seen[*it];
      EXPECT_TRUE(box.exteriorDistance(cloud.positions[*it]) < 1e-12);
    }
    EXPECT_TRUE(box.exteriorDistance(cells.medians[c]) < 1e-12);  // a median lies in its points' hull
    EXPECT_EQ(cells.find(cells.coordinates(c)), static_cast<std::int64_t>(c));
  }
  for (int s : seen) EXPECT_EQ(s, 1);
  EXPECT_EQ(cells.find(Eigen::Vector3i(-1, 0, 0)), -1);
}

/// A noisy vertical column of `n` points, seeded.
PointCloud column(std::size_t n) {
  std::mt19937 rng(7);
  std::normal_distribution<double> d(0.0, 0.05);
  std::uniform_real_distribution<double> z(0.0, 5.0);
  PointCloud c;
  for (std::size_t i = 0; i < n; ++i) c.positions.emplace_back(d(rng), d(rng), z(rng));
  return c;
}

// One stray point 20 times the cloud's size away is left out: the grid is the one without it.
TEST(Octree, AStrayPointFarAwayLeavesTheGridAsItWas) {
  const PointCloud plain = column(5000);
  PointCloud stray = plain;
  stray.positions.emplace_back(100.0, 0.0, 2.0);
  const OctreeCells a = build_octree_cells(plain), b = build_octree_cells(stray);
  ASSERT_EQ(b.outliers.size(), 1u);
  EXPECT_EQ(b.outliers[0], 5000u);
  EXPECT_TRUE(a.outliers.empty());
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_DOUBLE_EQ(a.cell_size, b.cell_size);
  EXPECT_EQ(a.keys, b.keys);
  // Points within the cloud's reach stay, however sparse.
  PointCloud near = plain;
  near.positions.emplace_back(2.0, 0.0, 2.0);
  EXPECT_TRUE(build_octree_cells(near).outliers.empty());
  // 0 keeps every point.
  OctreeOptions keep;
  keep.outlier_distance = 0.0;
  EXPECT_TRUE(build_octree_cells(stray, keep).outliers.empty());
}

// Every point written ten times: the same depth and the same cells.
TEST(Octree, RepeatedPointsCountOnce) {
  const PointCloud plain = column(5000);
  PointCloud repeated;
  for (int k = 0; k < 10; ++k)
    repeated.positions.insert(repeated.positions.end(), plain.positions.begin(), plain.positions.end());
  const OctreeCells a = build_octree_cells(plain), b = build_octree_cells(repeated);
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_EQ(a.keys, b.keys);
  for (std::size_t c = 0; c < a.cell_count(); ++c) EXPECT_EQ(10 * a.point_count(c), b.point_count(c));
  // Every copy after the first names the first.
  EXPECT_TRUE(a.repeats.empty());
  ASSERT_EQ(b.repeats.size(), 9u * 5000u);
  for (const auto& [point, first] : b.repeats) EXPECT_EQ(first, point % 5000u) << point;
}

// Repeats are the very same coordinates (-0 and +0 alike), among the cells' points and the outliers;
// points a hair apart, in one finest cell, are not repeats.
TEST(Octree, RepeatsAreExactlyTheSamePlace) {
  PointCloud c = column(2000);
  const std::uint32_t n = 2000;
  c.positions.push_back(c.positions[7]);                                        // n: repeats 7
  c.positions.push_back(c.positions[7] + Eigen::Vector3d(1e-12, 0.0, 0.0));      // n+1: a hair apart
  c.positions.push_back(c.positions[7]);                                        // n+2: repeats 7
  c.positions[3] = {0.0, 0.0, 1.0};
  c.positions.push_back({-0.0, 0.0, 1.0});                                      // n+3: repeats 3
  c.positions.push_back({500.0, 0.0, 0.0});                                     // n+4: an outlier
  c.positions.push_back({500.0, 0.0, 0.0});                                     // n+5: repeats it
  c.positions.push_back({500.0, 1e-9, 0.0});                                    // n+6: another outlier
  const OctreeCells cells = partition_octree(c);
  EXPECT_TRUE(cells.medians.empty());
  ASSERT_EQ(cells.outliers.size(), 3u);
  const std::vector<std::pair<std::uint32_t, std::uint32_t>> expected{{n, 7}, {n + 2, 7}, {n + 3, 3}, {n + 5, n + 4}};
  EXPECT_EQ(cells.repeats, expected);
  // The full build is the partition with its medians.
  const OctreeCells full = build_octree_cells(c);
  EXPECT_EQ(full.repeats, expected);
  EXPECT_EQ(full.keys, cells.keys);
  ASSERT_EQ(full.medians.size(), full.cell_count());
}

TEST(Octree, RejectsEmptyCloudAndBadDepth) {
  EXPECT_THROW(build_octree_cells(PointCloud{}, {}), InputError);
  PointCloud one;
  one.positions = {{0, 0, 0}, {1, 1, 1}};
  OctreeOptions bad;
  bad.depth = 22;
  EXPECT_THROW(build_octree_cells(one, bad), OptionError);
}

}  // namespace
}  // namespace treeskel
