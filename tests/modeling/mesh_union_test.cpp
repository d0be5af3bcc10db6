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
