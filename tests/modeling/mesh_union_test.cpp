// The union of closed tree meshes (modeling/src/mesh_union.h, private to the library).
#include "../../modeling/src/mesh_union.h"
#include "model_fixtures.h"
#include "treeskel/modeling/sweep.h"

#include <gtest/gtest.h>

namespace treeskel::modeling {
namespace {

void expect_valid(const TreeMesh& mesh) {
  const MeshCheck c = check_mesh(mesh);
  EXPECT_TRUE(c.ok()) << c.problem();
}

// A piece of a tree swept apart is united with the rest: a limb set beside a trunk whose join
// cannot take it still ends up in one closed mesh with the trunk.
TEST(MeshUnion, KeepsEveryPieceInOneMesh) {
  const TreeMesh trunk = sweep_mesh(test::straight(2.0, 0.1, 20));
  Skeleton limb;
  SkeletonNode a;
  a.position = Eigen::Vector3d(0, 0, 1);
  a.radius = 0.04;
  limb.root = add_node(limb, a);
  test::add_run(limb, limb.root, Eigen::Vector3d(1, 0, 1.5), 0.03, 10);
  const TreeMesh piece = sweep_mesh(limb);
  const auto united = detail::unite(trunk, {piece}, 1e-6 * 2.0);
  EXPECT_EQ(united.united, 1u);
  EXPECT_EQ(united.failed, 0u);
  expect_valid(united.mesh);
  const double sum = check_mesh(trunk).volume + check_mesh(piece).volume;
  EXPECT_LT(check_mesh(united.mesh).volume, sum);  // the overlap counts once
  EXPECT_GT(check_mesh(united.mesh).volume, check_mesh(trunk).volume);
}

// Two branches from different forks whose tubes run through each other: the repair thins the
// thinner one (by what clears it, not step by step) until the mesh no longer intersects itself.
TEST(SweepMesh, CrossingBranchesAreThinnedUntilTheyClear) {
  Skeleton s = test::straight(1.0, 0.1, 10);
  const NodeId low_fork = static_cast<NodeId>(s.node_count() - 1);
  const NodeId high_fork = test::add_run(s, low_fork, Eigen::Vector3d(0, 0, 2), 0.08, 10);
  test::add_run(s, high_fork, Eigen::Vector3d(0, 0, 2.8), 0.05, 8);
  // From the low fork, a branch rising gently along x; from the high one, a thinner branch coming
  // down onto it, whose last part comes within 0.075 of it (their radii sum to 0.09).
  SkeletonNode a_first, b_first;
  a_first.position = Eigen::Vector3d(0.1, 0, 1.02);
  a_first.radius = 0.05;
  b_first.position = Eigen::Vector3d(0.05, 0, 1.9);
  b_first.radius = 0.04;
  const NodeId a = add_node(s, a_first), b = add_node(s, b_first);
  boost::add_edge(low_fork, a, s.graph);
  boost::add_edge(high_fork, b, s.graph);
  test::add_run(s, a, Eigen::Vector3d(1.5, 0, 1.3), 0.05, 14);
  const NodeId bend = test::add_run(s, b, Eigen::Vector3d(0.3, 0, 1.5), 0.04, 5);
  test::add_run(s, bend, Eigen::Vector3d(1.2, 0, 1.24 + 0.075), 0.04, 9);

  SweepOptions no_repair;
  no_repair.repair = false;
  EXPECT_GT(check_mesh(sweep_mesh(s, no_repair)).self_intersections, 0u);  // they do cross

  SweepStats stats;
  const TreeMesh mesh = sweep_mesh(s, {}, &stats);
  expect_valid(mesh);
  EXPECT_EQ(stats.self_intersections, 0u);
  EXPECT_GE(stats.repair_rounds, 1);
  EXPECT_EQ(stats.attempts, 2);  // one round: x0.7 a round would have taken two
  EXPECT_EQ(stats.late_repair_rounds, 0);
  EXPECT_EQ(stats.repaired_dropped, 0u);
  EXPECT_GE(stats.repaired_shrunk, 1u);
}

TEST(MeshUnion, WeldsOnlyEdgesShorterThanTheDistance) {
  TreeMesh mesh = sweep_mesh(test::straight(2.0, 0.1, 20));
  const std::size_t before = mesh.n_vertices();
  EXPECT_EQ(detail::weld_short_edges(mesh, 1e-9), 0u);
  EXPECT_EQ(mesh.n_vertices(), before);
}

TEST(MeshUnion, PiecesApartStayAsTheirOwnComponents) {
  const TreeMesh a = sweep_mesh(test::straight(1.0, 0.1, 10));
  Skeleton far = test::straight(1.0, 0.1, 10);
  for (NodeId v = 0; v < far.node_count(); ++v) far[v].position.x() += 5.0;
  const auto united = detail::unite(a, {sweep_mesh(far)}, 1e-6);
  EXPECT_EQ(check_mesh(united.mesh).components, 2u);
  EXPECT_EQ(united.mesh.n_faces(), 2 * a.n_faces());
}

}  // namespace
}  // namespace treeskel::modeling
