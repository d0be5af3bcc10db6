#include "treeskel/level_sets.h"

#include "support/synthetic.h"

#include <gtest/gtest.h>

namespace treeskel {
namespace {

using test::tube;

/// The octree these tests were written for: 3 points a typical cell. (At the default 2, one ring of the
/// 8000-point cylinder below comes out of its band as a partial ring, 0.5 radii off the axis, which
/// the later stages put right; the level sets alone are tested here.) Whole depths, as then.
OctreeOptions three_a_cell() {
  OctreeOptions o;
  o.points_per_cell = 3.0;
  o.depth_steps = 1;
  return o;
}

Skeleton initial_skeleton(const PointCloud& cloud) {
  const OctreeCells cells = build_octree_cells(cloud, three_a_cell());
  const CellGraph graph = build_neighbour_graph(cells, {});
  const MainPart main = select_main_part(cells, graph);
  const auto geo = geodesic_distance(graph, select_root_cells(cells, graph, main.in_tree, {}));
  return level_set_skeleton(cloud, cells, graph, main.in_tree, geo, {});
}

TEST(LevelSets, CylinderGivesOneNodePerBandUpItsAxis) {
  const auto c = tube({0, 0, 0}, {0, 0, 1}, 0.05);
  eval::SurfaceSampling o;
  o.points = 8000;
  const PointCloud cloud = eval::sample_cylinders({c}, o);
  const Skeleton s = initial_skeleton(cloud);
  EXPECT_EQ(validate(s, cloud.size()), "");
  // One node per band of width 2 cells along the axis (the geodesic distance on the surface is the
  // height, less the root slice); the open top end may add a node or a spur of a few.
  const OctreeCells cells = build_octree_cells(cloud, three_a_cell());
  const double band = 2.0 * cells.cell_size;
  EXPECT_NEAR(static_cast<double>(s.node_count()), 1.0 / band, 5.0);
  EXPECT_LE(count_branch_points(s.graph), 1u);
  // Below the top, every node is near the axis (an L1-median of a sampled ring) and above its parent.
  const auto parent = parents_from_root(s.graph, s.root);
  for (NodeId v = 0; v < s.node_count(); ++v) {
    if (v == s.root || s[v].position.z() > 1.0 - 3 * band) continue;
    EXPECT_GT(s[v].position.z(), s[parent[v]].position.z());
    EXPECT_LT(s[v].position.head<2>().norm(), 0.4 * c.radius_a) << "z " << s[v].position.z();
  }
  // Radii by eq. 9 are close to the cylinder's (a band is a short tube, so slightly above r).
  for (NodeId v = 0; v < s.node_count(); ++v)
    if (v != s.root && boost::degree(v, s.graph) == 2) {
      EXPECT_NEAR(s[v].radius, 0.05, 0.01);
    }
}

TEST(LevelSets, MeanDistanceIsEquationNine) {
  const std::vector<Eigen::Vector3d> pts{{1, 0, 0}, {0, 2, 0}, {0, 0, 3}};
  EXPECT_DOUBLE_EQ(mean_distance(pts, {0, 1, 2}, Eigen::Vector3d::Zero()), 2.0);
  EXPECT_DOUBLE_EQ(mean_distance(pts, {}, Eigen::Vector3d::Zero()), 0.0);
}

TEST(LevelSets, UnreachedCellsBecomeNoise) {
  const auto c = tube({0, 0, 0}, {0, 0, 1}, 0.05);
  eval::SurfaceSampling o;
  o.points = 4000;
  PointCloud cloud = eval::sample_cylinders({c}, o);
  for (int i = 0; i < 5; ++i) cloud.positions.emplace_back(0.5 + 0.001 * i, 0.5, 0.5);  // a far tuft
  const Skeleton s = initial_skeleton(cloud);
  EXPECT_EQ(s.noise_points.size(), 5u);
  EXPECT_EQ(validate(s, cloud.size()), "");
}

}  // namespace
}  // namespace treeskel
