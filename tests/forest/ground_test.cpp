// Ground: the progressive morphological filter on planes, slopes, a block standing on the ground, a
// tree with no ground scanned, and a LAS classification; the ground under a single tree's scan.
#include "treeskel/error.h"
#include "treeskel/forest/ground.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace treeskel::forest {
namespace {

/// A grid of points every `step` on z = f(x, y) over [0, w] x [0, w].
template <class F>
void add_surface(PointCloud& cloud, double w, double step, F f) {
  for (double x = 0; x <= w + 1e-9; x += step)
    for (double y = 0; y <= w + 1e-9; y += step) cloud.positions.emplace_back(x, y, f(x, y));
}

TEST(Terrain, ElevationIsBilinearBetweenCellCentresAndFlatPastTheEdge) {
  Terrain t;
  t.cell = 1.0;
  t.nx = 2;
  t.ny = 2;
  t.z = {0.0, 1.0, 2.0, 3.0};  // (0,0) (1,0) / (0,1) (1,1)
  EXPECT_DOUBLE_EQ(t.elevation(0.5, 0.5), 0.0);
  EXPECT_DOUBLE_EQ(t.elevation(1.5, 0.5), 1.0);
  EXPECT_DOUBLE_EQ(t.elevation(1.0, 1.0), 1.5);
  EXPECT_DOUBLE_EQ(t.elevation(1.5, 1.5), 3.0);
  EXPECT_DOUBLE_EQ(t.elevation(-4.0, 0.5), 0.0);
  EXPECT_DOUBLE_EQ(t.elevation(9.0, 9.0), 3.0);
}

TEST(Ground, ASlopeIsAllGroundAndABlockOnItIsNot) {
  PointCloud cloud;
  auto ground_z = [](double x, double y) { return 0.3 * x + 0.1 * y; };
  add_surface(cloud, 20.0, 0.2, ground_z);
  const std::size_t ground_count = cloud.size();
  // A 3 m wide block, 2 m tall, standing at (10, 10): its top and sides.
  for (double x = 8.5; x <= 11.5; x += 0.1)
    for (double y = 8.5; y <= 11.5; y += 0.1) cloud.positions.emplace_back(x, y, ground_z(x, y) + 2.0);
  const Ground g = classify_ground(cloud);
  std::size_t missed = 0;
  for (std::size_t p = 0; p < ground_count; ++p) missed += !g.is_ground[p];
  // The ground under the block is hidden by it in plan (its lowest points are the block's): a
  // cell's points below the block's top are still the ground's.
  EXPECT_LT(missed, ground_count / 100);
  for (std::size_t p = ground_count; p < cloud.size(); ++p) {
    ASSERT_FALSE(g.is_ground[p]) << p;
    EXPECT_NEAR(g.height[p], 2.0, 0.35);
  }
  EXPECT_NEAR(g.terrain.elevation(5.0, 5.0) + cloud.offset.z(), ground_z(5.0, 5.0), 0.2);
}

TEST(Ground, ATreeScannedWithoutGroundStandsOnItsLowestPoint) {
  PointCloud cloud;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  // A trunk of radius 0.15 from z = 5 to 7, then a crown 4 m wide whose lowest twigs hang 0.8 m
  // above the trunk's base.
  for (int i = 0; i < 4000; ++i) {
    const double a = 2 * M_PI * u(rng);
    cloud.positions.emplace_back(0.15 * std::cos(a), 0.15 * std::sin(a), 5.0 + 2.0 * u(rng));
  }
  for (int i = 0; i < 8000; ++i)
    cloud.positions.emplace_back(4.0 * u(rng) - 2.0, 4.0 * u(rng) - 2.0, 5.8 + 3.0 * u(rng));
  const Ground g = classify_ground(cloud);
  for (double x : {-1.8, -1.0, 0.0, 1.0, 1.8})
    for (double y : {-1.8, 0.0, 1.8})
      EXPECT_NEAR(g.terrain.elevation(x - cloud.offset.x(), y - cloud.offset.y()) + cloud.offset.z(), 5.0, 0.05) << x << ' ' << y;
}

TEST(Ground, AClassificationIsTakenAsItIs) {
  PointCloud cloud;
  add_surface(cloud, 4.0, 0.5, [](double, double) { return 0.0; });
  cloud.positions.emplace_back(2.0, 2.0, 0.05);  // low, but classified as vegetation
  cloud.positions.emplace_back(2.0, 2.0, 3.0);
  std::vector<std::uint8_t> classes(cloud.size(), 2);
  classes[classes.size() - 2] = 3;
  classes.back() = 5;
  const Ground g = classify_ground(cloud, {}, &classes);
  for (std::size_t p = 0; p < cloud.size(); ++p) EXPECT_EQ(g.is_ground[p], classes[p] == 2) << p;
  EXPECT_EQ(g.ground_points, cloud.size() - 2);
}

TEST(Ground, RefusesAnEmptyCloudAndBadOptions) {
  EXPECT_THROW(classify_ground(PointCloud{}), InputError);
  PointCloud one;
  one.positions.emplace_back(0, 0, 0);
  GroundOptions bad;
  bad.cell = 0;
  EXPECT_THROW(classify_ground(one, bad), OptionError);
  const Ground g = classify_ground(one);
  EXPECT_EQ(g.ground_points, 1u);
}

/// A tree of one trunk (radius 0.13, 8 m) with a crown 4 m wide from 4 m up, seeded; with `ground`,
/// standing on a disc of ground 2.5 m across (noisy) with litter up to 0.25 m high on it.
/// Returns how many of the first points (the ground and the litter) there are.
std::size_t tree_on_ground(PointCloud& cloud, bool ground, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.01);
  if (ground) {
    for (double x = -2.5; x <= 2.5; x += 0.05)
      for (double y = -2.5; y <= 2.5; y += 0.05)
        if (std::hypot(x, y) > 0.16 && std::hypot(x, y) < 2.5) cloud.positions.emplace_back(x, y, noise(rng));
    for (int i = 0; i < 300; ++i) {  // litter and low plants, 0.5-2.5 m out
      const double a = 2 * M_PI * u(rng), r = 0.5 + 2.0 * u(rng);
      cloud.positions.emplace_back(r * std::cos(a), r * std::sin(a), 0.05 + 0.2 * u(rng));
    }
  }
  const std::size_t first = cloud.size();
  for (int i = 0; i < 6000; ++i) {
    const double a = 2 * M_PI * u(rng);
    cloud.positions.emplace_back(0.13 * std::cos(a), 0.13 * std::sin(a), 8.0 * u(rng));
  }
  for (int i = 0; i < 6000; ++i) cloud.positions.emplace_back(4.0 * u(rng) - 2.0, 4.0 * u(rng) - 2.0, 4.0 + 4.0 * u(rng));
  return first;
}

TEST(GroundUnderTree, AScanOfATreeOnItsGroundHasTheGroundAndWhatLiesOnItSetAside) {
  PointCloud cloud;
  const std::size_t ground_and_litter = tree_on_ground(cloud, true, 5);
  const GroundUnderTree g = ground_under_tree(cloud, Eigen::Vector3d::UnitZ());
  ASSERT_EQ(g.is_ground.size(), cloud.size());
  EXPECT_NEAR(g.stem_radius, 0.13, 0.01);
  EXPECT_GE(g.beyond_stem, 1000u);
  std::size_t kept = 0;
  for (std::size_t p = 0; p < ground_and_litter; ++p) kept += !g.is_ground[p];
  EXPECT_EQ(kept, 0u);  // the ground outside the stem, and the litter on it, all set aside
  for (std::size_t p = ground_and_litter; p < cloud.size(); ++p)
    if (cloud.positions[p].z() + cloud.offset.z() > 0.2) EXPECT_FALSE(g.is_ground[p]) << p;  // the tree is kept
  EXPECT_EQ(g.ground_points, static_cast<std::size_t>(std::count(g.is_ground.begin(), g.is_ground.end(), 1)));

  // The same cloud lying along y (scanned Y-up) gives the same points with up = y.
  PointCloud lying = cloud;
  for (auto& p : lying.positions) p = Eigen::Vector3d(p.x(), p.z(), -p.y());
  lying.offset = Eigen::Vector3d(cloud.offset.x(), cloud.offset.z(), -cloud.offset.y());
  const GroundUnderTree gy = ground_under_tree(lying, Eigen::Vector3d::UnitY());
  EXPECT_EQ(gy.is_ground, g.is_ground);
}

TEST(GroundUnderTree, ATreeScannedWithoutGroundKeepsEveryPoint) {
  PointCloud cloud;
  tree_on_ground(cloud, false, 5);
  const GroundUnderTree g = ground_under_tree(cloud, Eigen::Vector3d::UnitZ());
  EXPECT_EQ(g.ground_points, 0u);
  EXPECT_TRUE(g.is_ground.empty());
  // A patch of ground only under the stem's foot (within three stem radii) is the foot, not ground.
  std::mt19937_64 rng(2);
  std::normal_distribution<double> noise(0.0, 0.01);
  for (double x = -0.35; x <= 0.35; x += 0.03)
    for (double y = -0.35; y <= 0.35; y += 0.03)
      if (std::hypot(x, y) > 0.14 && std::hypot(x, y) < 0.35) cloud.positions.emplace_back(x, y, noise(rng));
  EXPECT_EQ(ground_under_tree(cloud, Eigen::Vector3d::UnitZ()).ground_points, 0u);
  // Not in metres (a tree 800 units tall): left as it is.
  PointCloud mm = cloud;
  for (auto& p : mm.positions) p *= 100.0;
  EXPECT_EQ(ground_under_tree(mm, Eigen::Vector3d::UnitZ()).ground_points, 0u);
}

}  // namespace
}  // namespace treeskel::forest
