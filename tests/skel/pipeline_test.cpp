#include "treeskel/pipeline.h"

#include "support/synthetic.h"
#include "treeskel/error.h"
#include "treeskel/io/point_cloud_io.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <map>

namespace treeskel {
namespace {

using test::tube;

TEST(Pipeline, StraightCylinderGivesOneCentredChain) {
  const auto c = tube({0, 0, 0}, {0, 0, 1}, 0.05);
  eval::SurfaceSampling o;
  o.points = 10000;
  const PointCloud cloud = eval::sample_cylinders({c}, o);
  const Skeleton s = extract_skeleton(cloud);
  EXPECT_EQ(validate(s, cloud.size()), "");
  EXPECT_EQ(count_branch_points(s.graph), 0u);
  EXPECT_EQ(count_endpoints(s.graph), 2u);
  EXPECT_LT(test::mean_distance_to_axis(s, c), 0.05 * c.radius_a);
}

TEST(Pipeline, YShapeGivesOneBranchPointAtTheFork) {
  const Eigen::Vector3d fork(0, 0, 1);
  const double r = 0.06;
  const std::vector<eval::Cylinder> y{tube({0, 0, 0}, fork, 0.08),
                                      tube(fork, fork + 0.7 * Eigen::Vector3d(1, 0, 1).normalized(), r),
                                      tube(fork, fork + 0.7 * Eigen::Vector3d(-1, 0, 1).normalized(), r)};
  for (unsigned seed = 1; seed <= 3; ++seed) {
    eval::SurfaceSampling o;
    o.points = 15000;
    o.seed = seed;
    const PointCloud cloud = eval::sample_cylinders(y, o);
    const Skeleton s = extract_skeleton(cloud);
    EXPECT_EQ(validate(s, cloud.size()), "");
    ASSERT_EQ(count_branch_points(s.graph), 1u) << "seed " << seed;
    EXPECT_EQ(count_endpoints(s.graph), 3u);
    for (NodeId v = 0; v < s.node_count(); ++v)
      if (boost::degree(v, s.graph) >= 3) {
        EXPECT_LT((s[v].position + s.offset - fork).norm(), 0.08) << "seed " << seed;
      }
  }
}

TEST(Pipeline, RejectsCloudsTheMethodCannotUse) {
  PointCloud few;
  few.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_THROW(extract_skeleton(few), InputError);
  PointCloud same;
  same.positions.assign(100, Eigen::Vector3d(1, 2, 3));
  EXPECT_THROW(extract_skeleton(same), InputError);
  PointCloud line;
  for (int i = 0; i < 100; ++i) line.positions.emplace_back(i, 2 * i, 3 * i);
  EXPECT_THROW(extract_skeleton(line), InputError);
  PointCloud nan;
  for (int i = 0; i < 100; ++i) nan.positions.emplace_back(i % 7, i % 5, i);
  nan.positions[50].x() = std::nan("");
  EXPECT_THROW(extract_skeleton(nan), InputError);
}

/// Every bundled real cloud, loaded once.
class RealClouds : public ::testing::TestWithParam<std::string> {
protected:
  static const PointCloud& cloud(const std::string& name) {
    static std::map<std::string, PointCloud> cache;
    auto it = cache.find(name);
    if (it == cache.end()) it = cache.emplace(name, io::read_point_cloud(test::data_file(name))).first;
    return it->second;
  }
};

bool same_skeleton(const Skeleton& a, const Skeleton& b, double tolerance, const Eigen::Vector3d& shift = Eigen::Vector3d::Zero()) {
  if (a.node_count() != b.node_count() || a.edge_count() != b.edge_count() || a.root != b.root) return false;
  for (NodeId v = 0; v < a.node_count(); ++v) {
    const Eigen::Vector3d pa = a[v].position + a.offset + shift, pb = b[v].position + b.offset;
    if ((pa - pb).norm() > tolerance || std::abs(a[v].radius - b[v].radius) > tolerance) return false;
    if (a[v].points != b[v].points) return false;
  }
  return a.noise_points == b.noise_points;
}

TEST_P(RealClouds, SkeletonIsATreeThatOwnsEveryPoint) {
  const PointCloud& c = cloud(GetParam());
  SkeletonStats stats;
  const Skeleton s = extract_skeleton(c, {}, &stats);
  EXPECT_EQ(validate(s, c.size()), "");
  EXPECT_EQ(s.left_out.total(), s.noise_points.size());
  EXPECT_GT(count_branch_points(s.graph), 3u);
  EXPECT_GT(count_endpoints(s.graph), 4u);
}

TEST_P(RealClouds, SameResultOnSecondRunAndWithOneOrTwoThreads) {
  const PointCloud& c = cloud(GetParam());
  const Skeleton first = extract_skeleton(c);
  const Skeleton second = extract_skeleton(c);
  EXPECT_TRUE(same_skeleton(first, second, 0.0));
  Skeleton single;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    single = extract_skeleton(c);
  }
  Skeleton two;
  {
    tbb::global_control both(tbb::global_control::max_allowed_parallelism, 2);
    two = extract_skeleton(c);
  }
  EXPECT_TRUE(same_skeleton(first, single, 0.0));
  EXPECT_TRUE(same_skeleton(first, two, 0.0));
}

TEST_P(RealClouds, UtmShiftedCopyGivesTheSameSkeletonShifted) {
  const PointCloud& c = cloud(GetParam());
  const Eigen::Vector3d shift(312345.678, 5012345.432, 250.5);
  PointCloud moved;
  for (const auto& p : c.positions) moved.positions.push_back(p + c.offset + shift);
  recentre_offset(moved);
  const Skeleton a = extract_skeleton(c), b = extract_skeleton(moved);
  const double size = bounding_box(c).sizes().norm();
  EXPECT_TRUE(same_skeleton(a, b, 1e-6 * size, shift));
}

TEST_P(RealClouds, AutomaticOptionsSpellOutTheDefaultsAndGiveTheSameSkeleton) {
  const PointCloud& c = cloud(GetParam());
  SkeletonStats stats;
  const Skeleton by_default = extract_skeleton(c, {}, &stats);
  const SkeletonOptions o = automatic_options(c);
  EXPECT_EQ(o.octree.depth, stats.octree_depth);
  EXPECT_DOUBLE_EQ(o.level_sets.band_width, stats.band_width);
  EXPECT_DOUBLE_EQ(o.level_sets.band_width, 2.0 * stats.cell_size);
  EXPECT_DOUBLE_EQ(o.prune.min_length, 0.5 * o.level_sets.band_width);
  EXPECT_DOUBLE_EQ(o.graph.bridge_distance, 4.0 * stats.cell_size);
  EXPECT_DOUBLE_EQ(o.root.slice, 2.0 * stats.cell_size);
  EXPECT_TRUE(same_skeleton(by_default, extract_skeleton(c, o), 0.0));
  // Values the caller set stay as they are.
  SkeletonOptions mine;
  mine.level_sets.band_width = 0.123;
  mine.graph.bridge_distance = -1.0;
  const SkeletonOptions kept = automatic_options(c, mine);
  EXPECT_EQ(kept.level_sets.band_width, 0.123);
  EXPECT_EQ(kept.prune.min_length, 0.5 * 0.123);
  EXPECT_EQ(kept.graph.bridge_distance, -1.0);
}

// AdTree's tree1 with one point 20 m away, and with every point repeated: the same skeleton (the
// stray point reported as left out, and noise).
TEST(Pipeline, AStrayPointOrRepeatedPointsChangeNothing) {
  const PointCloud tree = io::read_point_cloud(test::data_file("tree_adtree1.xyz"));
  const Skeleton plain = extract_skeleton(tree);
  PointCloud stray = tree;
  stray.positions.push_back(tree.positions.front() + Eigen::Vector3d(20.0, 0.0, 0.0));
  const Skeleton with_stray = extract_skeleton(stray);
  EXPECT_EQ(with_stray.node_count(), plain.node_count());
  EXPECT_EQ(with_stray.left_out.outliers, 1u);
  EXPECT_TRUE(std::binary_search(with_stray.noise_points.begin(), with_stray.noise_points.end(),
                                 static_cast<std::uint32_t>(tree.size())));
  EXPECT_EQ(validate(with_stray, stray.size()), "");
  PointCloud twice = tree;
  twice.positions.insert(twice.positions.end(), tree.positions.begin(), tree.positions.end());
  const Skeleton doubled = extract_skeleton(twice);
  EXPECT_NEAR(static_cast<double>(doubled.node_count()), static_cast<double>(plain.node_count()),
              0.01 * static_cast<double>(plain.node_count()));
  EXPECT_EQ(validate(doubled, twice.size()), "");
}

TEST(Pipeline, AutomaticOptionsRejectWhatExtractionRejects) {
  PointCloud few;
  few.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_THROW(automatic_options(few), InputError);
  EXPECT_THROW(automatic_options(PointCloud{}), InputError);
}

INSTANTIATE_TEST_SUITE_P(Bundled, RealClouds, ::testing::Values("tree_rtwig.txt", "tree_adtree1.xyz"),
                         [](const auto& info) { return info.param.substr(0, info.param.find('.')); });

}  // namespace
}  // namespace treeskel
