#include "modeling/model_fixtures.h"
#include "treeskel/modeling/coverage.h"
#include "treeskel/modeling/sweep.h"

#include <gtest/gtest.h>

namespace treeskel::modeling {
namespace {

TEST(Coverage, ASweptBranchHoldsItsWholeSkeleton) {
  const Skeleton s = test::straight(2.0, 0.05, 20);
  const TreeMesh mesh = sweep_mesh(s);
  const SkeletonCoverage c = skeleton_coverage(s, mesh);
  EXPECT_NEAR(c.length, 2.0, 1e-12);
  EXPECT_NEAR(c.share(), 1.0, 1e-9);
}

TEST(Coverage, AMeshOfHalfTheBranchHoldsHalfItsLength) {
  const Skeleton whole = test::straight(2.0, 0.05, 20);
  const TreeMesh half = sweep_mesh(test::straight(1.0, 0.05, 10));
  const SkeletonCoverage c = skeleton_coverage(whole, half);
  // The half mesh ends in a cone at 1.0: within one sample step of a half.
  EXPECT_NEAR(c.share(), 0.5, 0.01);
  EXPECT_DOUBLE_EQ(skeleton_coverage(whole, TreeMesh{}).share(), 0.0);
}

/// The unit cube [0, 1]^3, its faces turned outward.
TreeMesh unit_cube() {
  TreeMesh m;
  std::vector<TreeMesh::VertexHandle> v;
  for (int i = 0; i < 8; ++i) v.push_back(m.add_vertex(TreeMesh::Point(i & 1, (i >> 1) & 1, (i >> 2) & 1)));
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.add_face(v[q[0]], v[q[1]], v[q[2]]);
    m.add_face(v[q[0]], v[q[2]], v[q[3]]);
  }
  return m;
}

/// A skeleton of one edge across the cube's top, `lift` above it.
Skeleton above_the_top(double lift) {
  Skeleton s;
  SkeletonNode a, b;
  a.position = {0.2, 0.3, 1.0 + lift};
  b.position = {0.8, 0.6, 1.0 + lift};
  s.root = add_node(s, a);
  boost::add_edge(s.root, add_node(s, b), s.graph);
  return s;
}

TEST(Coverage, ASkeletonOutsideButWithinTheToleranceOfTheSurfaceIsCovered) {
  const TreeMesh cube = unit_cube();
  ASSERT_GT(check_mesh(cube).volume, 0.0);  // outward
  EXPECT_DOUBLE_EQ(skeleton_coverage(above_the_top(0.0), cube).share(), 1.0);          // on the surface
  EXPECT_DOUBLE_EQ(skeleton_coverage(above_the_top(-1e-3), cube).share(), 1.0);        // inside
  EXPECT_DOUBLE_EQ(skeleton_coverage(above_the_top(5e-4), cube, 0.0, 1e-3).share(), 1.0);  // outside, within
  EXPECT_DOUBLE_EQ(skeleton_coverage(above_the_top(2e-3), cube, 0.0, 1e-3).share(), 0.0);  // outside, beyond
  // From just above the top through the cube to just beside a side: within the tolerance of the side
  // face, then a little beyond it at the very end.
  Skeleton through = above_the_top(5e-4);
  through[1].position = {1.0 + 5e-4, 0.6, 0.5};
  EXPECT_DOUBLE_EQ(skeleton_coverage(through, cube, 0.0, 1e-3).share(), 1.0);
  through[1].position = {1.0 + 2e-3, 0.6, 0.5};
  const double share = skeleton_coverage(through, cube, 0.0, 1e-3).share();
  EXPECT_GT(share, 0.99);
  EXPECT_LT(share, 1.0);
}

/// One edge from (x0, 0.5, 0.5) to (x1, 0.5, 0.5), of radius `r` at both ends.
Skeleton rod(double x0, double x1, double r) {
  Skeleton s;
  SkeletonNode a, b;
  a.position = {x0, 0.5, 0.5};
  b.position = {x1, 0.5, 0.5};
  a.radius = b.radius = r;
  s.root = add_node(s, a);
  boost::add_edge(s.root, add_node(s, b), s.graph);
  return s;
}

TEST(Coverage, TheWoodInsideIsTheShareOfTheFrustumsTheMeshHolds) {
  const TreeMesh cube = unit_cube();
  // A rod of radius 0.1 wholly inside the cube, and one cut in half by its side x = 1.
  const WoodInside all = wood_inside(rod(0.2, 0.8, 0.1), cube);
  EXPECT_NEAR(all.volume, 3.14159265358979 * 0.01 * 0.6, 1e-12);
  EXPECT_EQ(all.samples, 4000u);
  EXPECT_EQ(all.inside, 4000u);
  const WoodInside half = wood_inside(rod(0.5, 1.5, 0.1), cube);
  EXPECT_NEAR(half.share(), 0.5, 0.03);  // 4,000 samples: a standard error of 0.008
  // A cone, its tip outside: a tenth of its length holds a thousandth of its volume.
  Skeleton cone = rod(0.1, 1.1, 0.1);
  cone[1].radius = 0.0;
  EXPECT_GT(wood_inside(cone, cube).share(), 0.99);
  // Seeded: the same points every time; another seed, other points.
  EXPECT_EQ(wood_inside(rod(0.5, 1.5, 0.1), cube).inside, half.inside);
  EXPECT_NE(wood_inside(rod(0.5, 1.5, 0.1), cube, 4000, 2).inside, half.inside);
  // Nothing to sample: no share lost. An empty mesh holds none of the wood.
  EXPECT_DOUBLE_EQ(wood_inside(rod(0.2, 0.8, 0.0), cube).share(), 1.0);
  EXPECT_EQ(wood_inside(rod(0.2, 0.8, 0.1), cube, 0).samples, 0u);
  EXPECT_DOUBLE_EQ(wood_inside(rod(0.2, 0.8, 0.1), TreeMesh{}).share(), 0.0);
}

TEST(Coverage, TheSkeletonsCoverageMeasuresTheWoodInsideToo) {
  // The same points as wood_inside's defaults, tested against the same mesh.
  const TreeMesh cube = unit_cube();
  const Skeleton half = rod(0.5, 1.5, 0.1);
  const SkeletonCoverage c = skeleton_coverage(half, cube);
  const WoodInside w = wood_inside(half, cube);
  EXPECT_EQ(c.wood.samples, kWoodSamples);
  EXPECT_EQ(c.wood.inside, w.inside);
  EXPECT_DOUBLE_EQ(c.wood.volume, w.volume);
  EXPECT_NEAR(c.share(), 0.5, 1e-3);
  EXPECT_DOUBLE_EQ(skeleton_coverage(half, TreeMesh{}).wood.share(), 0.0);
  // Asked for no wood samples: the length alone, the same as with them.
  const SkeletonCoverage length_only = skeleton_coverage(half, cube, 0.0, 0.0, 0);
  EXPECT_EQ(length_only.wood.samples, 0u);
  EXPECT_DOUBLE_EQ(length_only.inside_length, c.inside_length);
}

TEST(Coverage, FrustumsThatOverlapAreStillWoodInside) {
  // A Y's arms start inside the trunk's volume: the frustums count that part twice, and the mesh
  // once, so its volume falls short of theirs while all of their wood lies inside it.
  const Skeleton y = test::y_shape(0.1);
  const TreeMesh mesh = sweep_mesh(y);
  const WoodInside w = wood_inside(y, mesh);
  EXPECT_LT(check_mesh(mesh).volume, w.volume);
  EXPECT_GT(w.share(), 0.97);
  // A mesh of the trunk alone holds about its share of the wood.
  const TreeMesh trunk = sweep_mesh(test::straight(1.0, 0.1, 20));
  const double trunk_share = 0.01 / (0.01 + 2.0 * 0.005);  // r^2 L: trunk 0.01, each arm 0.005
  EXPECT_NEAR(wood_inside(y, trunk).share(), trunk_share, 0.04);
}

TEST(Coverage, SurfaceDistancesOfAxisAndOutsidePoints) {
  const TreeMesh mesh = sweep_mesh(test::straight(2.0, 0.1, 20));
  const std::vector<Eigen::Vector3d> points{{0, 0, 1}, {1, 0, 1}};
  const auto d = surface_distances(mesh, points);
  ASSERT_EQ(d.size(), 2u);
  // Polygons keep the circle's area: their sides lie a little inside the circle, their corners out.
  EXPECT_NEAR(d[0], 0.1, 0.01);
  EXPECT_NEAR(d[1], 0.9, 0.01);
  EXPECT_DOUBLE_EQ(share_within(d, 0.5), 0.5);
  EXPECT_DOUBLE_EQ(share_within({}, 1.0), 0.0);
}

}  // namespace
}  // namespace treeskel::modeling
