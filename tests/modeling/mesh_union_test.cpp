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

/// The mesh of a limb from the trunk's axis at height `z` to `to`, 0.04 thick at its start.
TreeMesh limb(double z, const Eigen::Vector3d& to) {
  Skeleton s;
  SkeletonNode a;
  a.position = Eigen::Vector3d(0, 0, z);
  a.radius = 0.04;
  s.root = add_node(s, a);
  test::add_run(s, s.root, to, 0.03, 10);
  return sweep_mesh(s);
}

// A piece of a tree swept apart is united with the rest: a limb set beside a trunk whose join
// cannot take it still ends up in one closed mesh with the trunk.
TEST(MeshUnion, KeepsEveryPieceInOneMesh) {
  const TreeMesh trunk = sweep_mesh(test::straight(2.0, 0.1, 20));
  const TreeMesh piece = limb(1.0, Eigen::Vector3d(1, 0, 1.5));
  const auto united = detail::unite(trunk, {piece}, 1e-6 * 2.0);
  EXPECT_EQ(united.united, 1u);
  EXPECT_EQ(united.failed, 0u);
  expect_valid(united.mesh);
  const double sum = check_mesh(trunk).volume + check_mesh(piece).volume;
  EXPECT_LT(check_mesh(united.mesh).volume, sum);  // the overlap counts once
  EXPECT_GT(check_mesh(united.mesh).volume, check_mesh(trunk).volume);
}

// Two limbs that cross each other are united between themselves first, then with the trunk in one
// corefinement: one closed mesh.
TEST(MeshUnion, PiecesThatCrossAreUnitedTogetherFirst) {
  const TreeMesh trunk = sweep_mesh(test::straight(2.0, 0.1, 20));
  const TreeMesh low = limb(0.8, Eigen::Vector3d(1, 0, 1.6));
  const TreeMesh high = limb(1.6, Eigen::Vector3d(1, 0, 0.8));  // crosses `low` at x = 0.5
  const TreeMesh apart = limb(1.0, Eigen::Vector3d(-1, 0, 1.2));
  const auto united = detail::unite(trunk, {low, high, apart}, 1e-6 * 2.0);
  EXPECT_EQ(united.united, 3u);
  EXPECT_EQ(united.failed, 0u);
  EXPECT_EQ(united.batches, 2u);  // low with high, then all with the trunk
  expect_valid(united.mesh);
}

TEST(MeshUnion, WeldsOnlyEdgesShorterThanTheDistance) {
  TreeMesh mesh = sweep_mesh(test::straight(2.0, 0.1, 20));
  const std::size_t before = mesh.n_vertices();
  EXPECT_EQ(detail::weld_short_edges(mesh, 1e-9), 0u);
  EXPECT_EQ(mesh.n_vertices(), before);
}

// Welding can be kept to boxes: a short edge outside them stays.
TEST(MeshUnion, WeldsOnlyWithinTheBoxesGiven) {
  const TreeMesh tube = sweep_mesh(test::straight(2.0, 0.1, 20));
  TreeMesh mesh = tube;
  // One vertex moved next to a neighbour: an edge 1e-9 long.
  const auto h = *mesh.voh_begin(mesh.vertex_handle(0));
  const auto from = mesh.from_vertex_handle(h), to = mesh.to_vertex_handle(h);
  mesh.set_point(to, mesh.point(from) + (mesh.point(to) - mesh.point(from)).normalized() * 1e-9);
  const auto p = mesh.point(from);
  const Eigen::Vector3d at(p[0], p[1], p[2]);
  TreeMesh kept = mesh;
  const Eigen::AlignedBox3d far(Eigen::Vector3d(5, 5, 5), Eigen::Vector3d(6, 6, 6));
  EXPECT_EQ(detail::weld_short_edges(kept, 1e-6, {far}), 0u);
  EXPECT_EQ(kept.n_vertices(), tube.n_vertices());
  const Eigen::AlignedBox3d near(at - Eigen::Vector3d::Constant(0.01), at + Eigen::Vector3d::Constant(0.01));
  EXPECT_EQ(detail::weld_short_edges(mesh, 1e-6, {near}), 1u);
  EXPECT_EQ(mesh.n_vertices(), tube.n_vertices() - 1);
}

TEST(MeshUnion, PiecesApartStayAsTheirOwnComponents) {
  const TreeMesh a = sweep_mesh(test::straight(1.0, 0.1, 10));
  Skeleton far = test::straight(1.0, 0.1, 10);
  for (NodeId v = 0; v < far.node_count(); ++v) far[v].position.x() += 5.0;
  const auto united = detail::unite(a, {sweep_mesh(far)}, 1e-6);
  EXPECT_EQ(check_mesh(united.mesh).components, 2u);
  EXPECT_EQ(united.mesh.n_faces(), 2 * a.n_faces());
}

// A piece the union refuses (here: open, one face missing) is returned beside the mesh, not in it:
// joined into it, it broke the precondition of every corefinement after it, and the limb that
// crosses it through the trunk was refused too (or CGAL crashed).
TEST(MeshUnion, ARefusedPieceDoesNotSpoilTheUnionsAfterIt) {
  const TreeMesh trunk = sweep_mesh(test::straight(2.0, 0.1, 20));
  TreeMesh open = limb(0.8, Eigen::Vector3d(1, 0, 1.6));
  open.request_face_status();
  open.request_edge_status();
  open.request_vertex_status();
  open.delete_face(*open.faces_begin(), false);
  open.garbage_collection();
  const TreeMesh crossing = limb(1.6, Eigen::Vector3d(1, 0, 0.8));  // crosses `open` at x = 0.5
  const auto united = detail::unite(trunk, {open, crossing}, 1e-6 * 2.0);
  EXPECT_EQ(united.failed, 1u);
  EXPECT_EQ(united.united, 1u);
  EXPECT_EQ(united.mesh.n_faces(), detail::unite(trunk, {crossing}, 1e-6 * 2.0).mesh.n_faces());
  EXPECT_EQ(united.apart.n_faces(), open.n_faces());  // beside the mesh, for the caller to add last
  expect_valid(united.mesh);
}

}  // namespace
}  // namespace treeskel::modeling
