// The union of closed tree meshes (modeling/src/mesh_union.h, private to the library).
#include "../../modeling/src/mesh_union.h"
#include "model_fixtures.h"
#include "treeskel/modeling/sweep.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

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

// How deep a point lies in a trunk swept 0.1 thick up to z = 2: along its axis a radius deep (a little
// less: the rings are polygons of the circle's area), beside it the distance to its surface, negative.
TEST(MeshUnion, MeshDepthIsTheSignedDistanceToTheSurface) {
  const TreeMesh trunk = sweep_mesh(test::straight(2.0, 0.1, 20));
  const detail::MeshDepth depth(trunk);
  EXPECT_NEAR(depth(Eigen::Vector3d(0, 0, 1.0)), 0.1, 0.01);
  EXPECT_NEAR(depth(Eigen::Vector3d(0.05, 0, 1.0)), 0.05, 0.01);
  EXPECT_NEAR(depth(Eigen::Vector3d(0.3, 0, 1.0)), -0.2, 0.01);
  EXPECT_LT(depth(Eigen::Vector3d(0, 0, 2.5)), -0.45);  // above its top
  // The nearest point of the surface: on it, as far as the depth says, and the point itself there.
  for (const Eigen::Vector3d p : {Eigen::Vector3d(0.3, 0, 1.0), Eigen::Vector3d(0.05, 0, 1.0), Eigen::Vector3d(0, 0.4, 0.5)}) {
    const Eigen::Vector3d q = depth.nearest(p);
    EXPECT_NEAR(depth(q), 0.0, 1e-9);
    EXPECT_NEAR((q - p).norm(), std::abs(depth(p)), 1e-9);
    EXPECT_NEAR((depth.nearest(q) - q).norm(), 0.0, 1e-9);
  }
  const detail::MeshDepth none{TreeMesh()};
  EXPECT_LT(none(Eigen::Vector3d::Zero()), -1e300);
  EXPECT_EQ(none.nearest(Eigen::Vector3d(1, 2, 3)), Eigen::Vector3d(1, 2, 3));
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

// A group's union made by an earlier call is taken again for the same pieces: the same mesh, one
// corefinement fewer. A piece moved (as a nudge moves it) makes its group again.
TEST(MeshUnion, AGroupOfTheSamePiecesIsNotUnitedAgain) {
  const TreeMesh trunk = sweep_mesh(test::straight(2.0, 0.1, 20));
  const TreeMesh low = limb(0.8, Eigen::Vector3d(1, 0, 1.6));
  const TreeMesh high = limb(1.6, Eigen::Vector3d(1, 0, 0.8));  // crosses `low` at x = 0.5
  const TreeMesh apart = limb(1.0, Eigen::Vector3d(-1, 0, 1.2));
  detail::GroupUnions made;
  const auto first = detail::unite(trunk, {low, high, apart}, 1e-6 * 2.0, Eigen::Vector3d::Zero(), {}, false, &made);
  EXPECT_EQ(first.batches, 2u);  // low with high, then all with the trunk
  const auto again = detail::unite(trunk, {low, high, apart}, 1e-6 * 2.0, Eigen::Vector3d::Zero(), {}, false, &made);
  EXPECT_EQ(again.batches, 1u);  // with the trunk only
  EXPECT_EQ(again.united, 3u);
  ASSERT_EQ(again.mesh.n_vertices(), first.mesh.n_vertices());
  ASSERT_EQ(again.mesh.n_faces(), first.mesh.n_faces());
  for (auto v : first.mesh.vertices()) EXPECT_EQ(again.mesh.point(v), first.mesh.point(v));
  for (auto f : first.mesh.faces()) {
    auto a = first.mesh.cfv_begin(f), b = again.mesh.cfv_begin(again.mesh.face_handle(static_cast<unsigned>(f.idx())));
    for (int k = 0; k < 3; ++k, ++a, ++b) EXPECT_EQ(a->idx(), b->idx());
  }
  TreeMesh moved = high;
  for (auto v : moved.vertices()) moved.set_point(v, moved.point(v) + TreeMesh::Point(0, 0.001, 0));
  const auto nudged = detail::unite(trunk, {low, moved, apart}, 1e-6 * 2.0, Eigen::Vector3d::Zero(), {}, false, &made);
  EXPECT_EQ(nudged.batches, 2u);
  expect_valid(nudged.mesh);
}

/// The mesh of a straight branch from `from` to `to`, `radius` thick.
TreeMesh rod(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double radius) {
  Skeleton s;
  SkeletonNode a;
  a.position = from;
  a.radius = radius;
  s.root = add_node(s, a);
  test::add_run(s, s.root, to, radius, 8);
  return sweep_mesh(s);
}

// More crossing pieces than a group takes: a thick bar through nine thin limbs that pass one
// another close by without touching. The bar's group takes seven of them; the two left over make
// a round of their own, one corefinement with the whole, where two layers took two (their boxes
// overlap, though the limbs do not meet).
TEST(MeshUnion, PiecesAFullGroupLeavesMakeARoundOfTheirOwn) {
  const TreeMesh trunk = sweep_mesh(test::straight(2.2, 0.1, 22));
  std::vector<TreeMesh> pieces{rod(Eigen::Vector3d(0, 0, 1.0), Eigen::Vector3d(1.5, 0, 1.0), 0.15)};
  for (int i = 0; i < 9; ++i) {
    // Side by side, a little apart; the last two in one plane, so that their boxes overlap.
    const double z = 1.2 + 0.1 * i, y = i % 2 || i == 8 ? 0.05 : -0.05;
    pieces.push_back(rod(Eigen::Vector3d(0, y, z), Eigen::Vector3d(1.2, y, z - 1.2), 0.03));
  }
  const auto united = detail::unite(trunk, pieces, 1e-6 * 2.2);
  EXPECT_EQ(united.united, 10u);
  EXPECT_EQ(united.failed, 0u);
  EXPECT_EQ(united.skipped, 0u);
  EXPECT_EQ(united.batches, 9u);  // seven into the bar's group, it with the trunk, then the two left
  expect_valid(united.mesh);
}

// The sweep of a tree can leave every branch apart and hold nothing itself (seed 2's
// tree1_vdensity_3 did: its first union then read the side of a point in an empty mesh, and crashed).
// United with nothing, the pieces are the whole: one closed mesh of both, none left apart.
TEST(MeshUnion, PiecesUniteWithAnEmptyBase) {
  const TreeMesh low = limb(0.8, Eigen::Vector3d(1, 0, 1.6));
  const TreeMesh apart = limb(1.0, Eigen::Vector3d(-1, 0, 1.2));
  const auto united = detail::unite(TreeMesh{}, {low, apart}, 1e-6 * 2.0);
  EXPECT_EQ(united.united, 2u);
  EXPECT_EQ(united.failed, 0u);
  EXPECT_EQ(united.mesh.n_faces(), low.n_faces() + apart.n_faces());
  const MeshCheck c = check_mesh(united.mesh);
  EXPECT_EQ(c.boundary_edges, 0u);
  EXPECT_EQ(c.non_manifold_vertices, 0u);
  EXPECT_EQ(c.self_intersections, 0u);
  EXPECT_EQ(c.components, 2u);  // the two limbs, apart from each other as they were swept
}

/// The points of `mesh`'s faces, corner by corner, in face order.
std::vector<TreeMesh::Point> face_corners(const TreeMesh& mesh) {
  std::vector<TreeMesh::Point> out;
  for (auto f : mesh.faces())
    for (auto v : mesh.fv_range(f)) out.push_back(mesh.point(v));
  return out;
}

// Groups of crossing pieces are united side by side; one thread gives the same mesh as two.
TEST(MeshUnion, OneThreadOrTwoGiveTheSameMesh) {
  const TreeMesh trunk = sweep_mesh(test::straight(2.0, 0.1, 20));
  const std::vector<TreeMesh> pieces{limb(0.8, Eigen::Vector3d(1, 0, 1.6)), limb(1.6, Eigen::Vector3d(1, 0, 0.8)),
                                     limb(0.5, Eigen::Vector3d(-1, 0, 1.3)), limb(1.3, Eigen::Vector3d(-1, 0, 0.5))};
  const auto two = detail::unite(trunk, pieces, 1e-6 * 2.0);
  EXPECT_EQ(two.united, 4u);
  EXPECT_EQ(two.batches, 3u);  // the two pairs, then both with the trunk
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  const auto one = detail::unite(trunk, pieces, 1e-6 * 2.0);
  EXPECT_EQ(face_corners(one.mesh), face_corners(two.mesh));
}

/// A closed tetrahedron, its faces turned outward.
TreeMesh tetrahedron(const TreeMesh::Point& p, const TreeMesh::Point& q, const TreeMesh::Point& r, const TreeMesh::Point& t) {
  TreeMesh m;
  std::array<TreeMesh::VertexHandle, 4> v{m.add_vertex(p), m.add_vertex(q), m.add_vertex(r), m.add_vertex(t)};
  if (OpenMesh::dot(OpenMesh::cross(q - p, r - p), t - p) > 0) std::swap(v[1], v[2]);  // t below p, q, r's face
  m.add_face(v[0], v[1], v[2]);
  m.add_face(v[0], v[3], v[1]);
  m.add_face(v[1], v[3], v[2]);
  m.add_face(v[2], v[3], v[0]);
  return m;
}

// A solid whose tip touches another's face at a single point: the union keeps both whole, closed
// and manifold, the point twice (the tip, and the vertex corefinement puts in the face it touches),
// not one vertex that two fans of faces would share.
TEST(MeshUnion, SolidsTouchingAtAPointKeepEveryFace) {
  using P = TreeMesh::Point;
  const TreeMesh a = tetrahedron(P(0, 0, 0), P(1, 0, 0), P(0, 1, 0), P(0, 0, 1));
  const TreeMesh b = tetrahedron(P(0.25, 0.25, 0), P(0.75, 0.25, -1), P(-0.25, 0.5, -1), P(0.25, -0.25, -1));
  ASSERT_GT(check_mesh(a).volume, 0.0);
  ASSERT_GT(check_mesh(b).volume, 0.0);
  const auto united = detail::unite(a, {b}, 1e-9);
  EXPECT_EQ(united.united, 1u);
  const MeshCheck c = check_mesh(united.mesh);
  EXPECT_EQ(c.boundary_edges, 0u);
  EXPECT_EQ(c.non_manifold_vertices, 0u);
  EXPECT_EQ(c.components, 2u);
  EXPECT_NEAR(c.volume, check_mesh(a).volume + check_mesh(b).volume, 1e-12);
  // The touching point twice: the face it cuts in three, and b's tip.
  std::size_t at_tip = 0;
  for (auto v : united.mesh.vertices()) at_tip += united.mesh.point(v) == P(0.25, 0.25, 0) ? 1 : 0;
  EXPECT_EQ(at_tip, 2u);
}

// Pieces whose surfaces touch at a single point are one group (one union between them); a piece
// inside the other's box but apart from its surface is not (it is joined as it is, no union). With
// nothing to unite them with, the group's union is the only corefinement.
TEST(MeshUnion, PiecesTouchingAtAPointAreOneGroupPiecesOnlyInABoxAreNot) {
  using P = TreeMesh::Point;
  const TreeMesh a = tetrahedron(P(0, 0, 0), P(1, 0, 0), P(0, 1, 0), P(0, 0, 1));
  const TreeMesh touching = tetrahedron(P(0.25, 0.25, 0), P(0.75, 0.25, -1), P(-0.25, 0.5, -1), P(0.25, -0.25, -1));
  const TreeMesh in_box = tetrahedron(P(0.8, 0.8, 0.8), P(0.9, 0.8, 0.8), P(0.8, 0.9, 0.8), P(0.8, 0.8, 0.9));
  const auto united = detail::unite(TreeMesh{}, {a, touching, in_box}, 1e-9);
  EXPECT_EQ(united.united, 3u);
  EXPECT_EQ(united.failed, 0u);
  EXPECT_EQ(united.batches, 1u);
  const MeshCheck c = check_mesh(united.mesh);
  EXPECT_EQ(c.components, 3u);
  EXPECT_NEAR(c.volume, check_mesh(a).volume + check_mesh(touching).volume + check_mesh(in_box).volume, 1e-9);  // points rounded to floats
  // Apart, they are three groups and no union.
  const TreeMesh away = tetrahedron(P(3, 0, 0), P(4, 0, 0), P(3, 1, 0), P(3, 0, 1));
  EXPECT_EQ(detail::unite(TreeMesh{}, {a, away, in_box}, 1e-9).batches, 0u);
}

// A piece wholly inside another (their surfaces apart) is one group with it, as a crossing piece is:
// the two are united first, then with the trunk, rather than joined side by side into one
// corefinement with the trunk.
TEST(MeshUnion, APieceInsideAnotherIsUnitedWithItFirst) {
  using P = TreeMesh::Point;
  const TreeMesh trunk = sweep_mesh(test::straight(2.0, 0.1, 20));
  const TreeMesh outer = limb(1.0, Eigen::Vector3d(1, 0, 1.5));
  const double e = 0.004;  // well inside the limb (radius 0.03-0.04) around its axis at x = 0.6
  const TreeMesh inner = tetrahedron(P(0.6, 0, 1.3), P(0.6 + e, 0, 1.3), P(0.6, e, 1.3), P(0.6, 0, 1.3 + e));
  const auto united = detail::unite(trunk, {outer, inner}, 1e-6 * 2.0);
  EXPECT_EQ(united.united, 2u);
  EXPECT_EQ(united.failed, 0u);
  EXPECT_EQ(united.batches, 2u);  // inner into outer, then the group with the trunk
  expect_valid(united.mesh);
  EXPECT_EQ(check_mesh(united.mesh).components, 1u);
}

// A vertex shared by fans of faces that share no edge from it is split, a copy per fan after the
// first, in the order of the fans' first faces; a vertex with one fan stays as it is.
TEST(MeshUnion, PinchedVerticesGetACopyPerFan) {
  using Face = std::array<std::size_t, 3>;
  auto tetrahedron_faces = [](std::size_t a, std::size_t b, std::size_t c, std::size_t d) {
    return std::vector<Face>{{a, b, c}, {a, d, b}, {b, d, c}, {c, d, a}};
  };
  std::vector<std::array<double, 3>> points(10);
  for (std::size_t i = 0; i < points.size(); ++i) points[i] = {double(i), 0.5 * double(i), 0.0};
  std::vector<Face> faces;
  for (const auto& part : {tetrahedron_faces(0, 1, 2, 3), tetrahedron_faces(4, 0, 5, 6), tetrahedron_faces(7, 8, 0, 9)})
    faces.insert(faces.end(), part.begin(), part.end());
  const std::vector<Face> before = faces;
  detail::split_pinched_vertices(points, faces);
  ASSERT_EQ(points.size(), 12u);
  EXPECT_EQ(points[10], points[0]);
  EXPECT_EQ(points[11], points[0]);
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t expected = before[f][k] != 0 ? before[f][k] : f < 4 ? 0 : f < 8 ? 10 : 11;
      EXPECT_EQ(faces[f][k], expected) << "face " << f << " corner " << k;
    }
  std::vector<Face> one = tetrahedron_faces(0, 1, 2, 3);
  std::vector<std::array<double, 3>> four(points.begin(), points.begin() + 4);
  detail::split_pinched_vertices(four, one);
  EXPECT_EQ(four.size(), 4u);
  EXPECT_EQ(one, tetrahedron_faces(0, 1, 2, 3));
}

// Corefinement lists its vertices in an order that follows memory addresses. Points that a double
// cannot tell apart take the order of their exact points, and the same exact point twice (two parts
// touching) the order of its neighbours', whatever order they came in.
TEST(MeshUnion, VerticesAtOneDoubleTakeTheOrderOfTheirExactPoints) {
  // Five vertices rounding to one point: exact points 5, 3, 9, 3 and 1 (a rank stands for one), the
  // two at 3 with neighbours at 1 and at 9.
  const std::vector<int> exact{5, 3, 9, 3, 1};
  const std::vector<std::vector<std::size_t>> neighbours_of{{}, {4}, {}, {2}, {}};
  const std::vector<std::size_t> expected{4, 1, 3, 0, 2};
  std::vector<std::size_t> arrival{0, 1, 2, 3, 4};  // arrival[i]: the vertex listed i-th
  int orders = 0;
  do {
    std::vector<std::size_t> listed_at(arrival.size());
    for (std::size_t i = 0; i < arrival.size(); ++i) listed_at[arrival[i]] = i;
    const std::vector<std::array<double, 3>> same(arrival.size(), std::array<double, 3>{1.0, 2.0, 3.0});
    const auto exact_less = [&](std::size_t a, std::size_t b) { return exact[arrival[a]] < exact[arrival[b]]; };
    const auto neighbours = [&](std::size_t i) {
      std::vector<std::size_t> out;
      for (std::size_t v : neighbours_of[arrival[i]]) out.push_back(listed_at[v]);
      return out;
    };
    const auto order = detail::canonical_vertex_order(same, same, exact_less, neighbours);
    std::vector<std::size_t> vertices;
    for (std::size_t i : order) vertices.push_back(arrival[i]);
    EXPECT_EQ(vertices, expected) << "listed in the order of permutation " << orders;
    ++orders;
  } while (std::next_permutation(arrival.begin(), arrival.end()));
  EXPECT_EQ(orders, 120);
  // Rounded points and doubles come first.
  std::vector<std::array<double, 3>> rounded(5, std::array<double, 3>{1.0, 2.0, 3.0}), unrounded = rounded;
  rounded[4][0] = 2.0;
  unrounded[2][1] = 1.0;
  const auto plain = [&](std::size_t a, std::size_t b) { return exact[a] < exact[b]; };
  const auto none = [](std::size_t) { return std::vector<std::size_t>{}; };
  EXPECT_EQ(detail::canonical_vertex_order(rounded, unrounded, plain, none), (std::vector<std::size_t>{2, 1, 3, 0, 4}));
}

TEST(MeshUnion, WeldsOnlyEdgesShorterThanTheDistance) {
  TreeMesh mesh = sweep_mesh(test::straight(2.0, 0.1, 20));
  const std::size_t before = mesh.n_vertices();
  EXPECT_EQ(detail::weld_short_edges(mesh, 1e-9), 0u);
  EXPECT_EQ(mesh.n_vertices(), before);
}

/// A closed, outward box from `lo` to `hi` (12 triangles).
TreeMesh box_mesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  TreeMesh mesh;
  std::vector<TreeMesh::VertexHandle> v;
  for (int i = 0; i < 8; ++i)
    v.push_back(mesh.add_vertex(TreeMesh::Point(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z())));
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    mesh.add_face(v[q[0]], v[q[1]], v[q[2]]);
    mesh.add_face(v[q[0]], v[q[2]], v[q[3]]);
  }
  return mesh;
}

/// The faces of `mesh` as their corner positions (each face's sorted), sorted.
std::vector<std::array<std::array<double, 3>, 3>> sorted_faces(const TreeMesh& mesh) {
  std::vector<std::array<std::array<double, 3>, 3>> out;
  for (auto f : mesh.faces()) {
    std::array<std::array<double, 3>, 3> c{};
    std::size_t k = 0;
    for (auto v : mesh.fv_range(f)) {
      const auto p = mesh.point(v);
      c[k++] = {p[0], p[1], p[2]};
    }
    std::sort(c.begin(), c.end());
    out.push_back(c);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The sliver rounds after a union test again only where a collapse changed the mesh: each collapse
// gives a box that holds every face it changed, as it was and as it became.
TEST(MeshUnion, EachCollapseSaysWhereItChangedTheMesh) {
  TreeMesh mesh = sweep_mesh(test::y_shape(0.05, 0.6, 20));
  const auto before = sorted_faces(mesh);
  std::vector<std::size_t> faces;
  for (std::size_t f = 0; f < mesh.n_faces(); f += 97) faces.push_back(f);
  std::vector<Eigen::AlignedBox3d> moved;
  const std::size_t collapsed = detail::collapse_shortest_edges(mesh, faces, 1.0, 0.0, &moved);
  EXPECT_GT(collapsed, 10u);
  EXPECT_EQ(moved.size(), collapsed);
  expect_valid(mesh);
  const auto after = sorted_faces(mesh);
  auto held = [&](const std::array<std::array<double, 3>, 3>& c) {
    return std::any_of(moved.begin(), moved.end(), [&](const Eigen::AlignedBox3d& b) {
      return std::all_of(c.begin(), c.end(), [&](const std::array<double, 3>& p) { return b.contains(Eigen::Vector3d(p[0], p[1], p[2])); });
    });
  };
  std::size_t changed = 0;
  for (const auto& c : after)
    if (!std::binary_search(before.begin(), before.end(), c)) {
      ++changed;
      EXPECT_TRUE(held(c));
    }
  for (const auto& c : before)
    if (!std::binary_search(after.begin(), after.end(), c)) EXPECT_TRUE(held(c));
  EXPECT_GT(changed, 0u);
}

// Where a face's shortest edge may not collapse (its ends have three neighbours in common, and the
// collapse would pinch the mesh), its next edge does: a bipyramid's equator edge is the shortest.
TEST(MeshUnion, AFaceWhoseShortestEdgeMayNotGoLosesItsNext) {
  TreeMesh mesh;
  const double h = 1.0;
  std::vector<TreeMesh::VertexHandle> v;
  for (int k = 0; k < 3; ++k)
    v.push_back(mesh.add_vertex(TreeMesh::Point(std::cos(2.0944 * k) / std::sqrt(3.0), std::sin(2.0944 * k) / std::sqrt(3.0), 0.0)));
  const auto top = mesh.add_vertex(TreeMesh::Point(0, 0, h)), bottom = mesh.add_vertex(TreeMesh::Point(0, 0, -h));
  for (int k = 0; k < 3; ++k) {
    mesh.add_face(v[k], v[(k + 1) % 3], top);
    mesh.add_face(v[(k + 1) % 3], v[k], bottom);
  }
  ASSERT_TRUE(check_mesh(mesh, false).ok());
  // Face 0 is (v0, v1, top); its shortest edge v0-v1 (length 1) has v2, top and bottom around both ends.
  EXPECT_EQ(detail::collapse_shortest_edges(mesh, {0}, 1.1), 0u);  // the only edge no longer than 1.1
  EXPECT_EQ(detail::collapse_shortest_edges(mesh, {0}, 2.0), 1u);
  EXPECT_EQ(mesh.n_faces(), 4u);  // a tetrahedron
  expect_valid(mesh);
}

// A sliver round that made no progress takes the faces around the crossing ones too: on a box, the
// faces that share a corner with one of its triangles.
TEST(MeshUnion, FacesAroundAreThoseSharingACorner) {
  const TreeMesh box = box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());
  const auto around = detail::faces_around(box, {0});
  std::vector<std::size_t> expected;
  for (auto f : box.faces()) {
    bool shares = false;
    for (auto v : box.fv_range(f))
      for (auto w : box.fv_range(box.face_handle(0u))) shares = shares || v == w;
    if (shares) expected.push_back(static_cast<std::size_t>(f.idx()));
  }
  EXPECT_EQ(around, expected);
  EXPECT_LT(around.size(), box.n_faces());  // not every face: the far corner's are left
  EXPECT_EQ(detail::faces_around(box, {3, 3}), detail::faces_around(box, {3}));
}

// Pieces that close a pocket of air with the tree leave its inward surface as a component of its
// own (seed 4's tree5_missing_3: a tetrahedron 0.1 mm across); wood has no voids, and it is filled.
TEST(MeshUnion, AVoidThePiecesEncloseIsFilled) {
  // A hollow box of six slabs 0.2 thick, overlapping at the edges: the floor is the tree, the walls
  // and the lid are pieces.
  const TreeMesh floor = box_mesh({0, 0, 0}, {1, 1, 0.2});
  const std::vector<TreeMesh> walls{box_mesh({0, 0, 0.1}, {0.2, 1, 1}), box_mesh({0.8, 0, 0.1}, {1, 1, 1}),
                                    box_mesh({0.1, 0, 0.1}, {0.9, 0.2, 1}), box_mesh({0.1, 0.8, 0.1}, {0.9, 1, 1}),
                                    box_mesh({0, 0, 0.8}, {1, 1, 1})};
  ASSERT_TRUE(check_mesh(floor).ok());
  const auto r = detail::unite(floor, walls, 1e-9);
  EXPECT_EQ(r.united, walls.size());
  EXPECT_EQ(r.voids, 1u);
  const MeshCheck c = check_mesh(r.mesh);
  EXPECT_TRUE(c.ok()) << c.problem();
  EXPECT_EQ(c.components, 1u);
  EXPECT_NEAR(c.volume, 1.0, 1e-6);  // the whole box: the 0.6 x 0.6 x 0.6 void is wood now
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

// A piece whose surface meets none of the tree's is added as it is, without a corefinement.
TEST(MeshUnion, PiecesApartStayAsTheirOwnComponents) {
  const TreeMesh a = sweep_mesh(test::straight(1.0, 0.1, 10));
  Skeleton far = test::straight(1.0, 0.1, 10);
  for (NodeId v = 0; v < far.node_count(); ++v) far[v].position.x() += 5.0;
  const auto united = detail::unite(a, {sweep_mesh(far)}, 1e-6);
  EXPECT_EQ(united.united, 1u);
  EXPECT_EQ(united.batches, 0u);
  EXPECT_EQ(check_mesh(united.mesh).components, 2u);
  EXPECT_EQ(united.mesh.n_faces(), 2 * a.n_faces());
}

// One corefinement takes the pieces that cross the tree; the one apart from it is added beside
// them, the one inside it is dropped: the mesh is the one the crossing piece alone gives, plus the
// piece apart.
TEST(MeshUnion, OnlyPiecesThatMeetTheTreeAreCorefined) {
  using P = TreeMesh::Point;
  const TreeMesh trunk = sweep_mesh(test::straight(2.0, 0.1, 20));
  const TreeMesh crossing = limb(1.0, Eigen::Vector3d(1, 0, 1.5));
  const TreeMesh apart = limb(1.0, Eigen::Vector3d(-1, 0, 1.5));
  TreeMesh away = apart;
  for (auto v : away.vertices()) away.set_point(v, away.point(v) + P(-0.5, 0, 0));  // clear of the trunk
  const double e = 0.01;  // well inside the trunk (radius 0.1)
  const TreeMesh inside = tetrahedron(P(0, 0, 0.5), P(e, 0, 0.5), P(0, e, 0.5), P(0, 0, 0.5 + e));
  const auto united = detail::unite(trunk, {crossing, away, inside}, 1e-6 * 2.0);
  EXPECT_EQ(united.united, 3u);
  EXPECT_EQ(united.batches, 1u);
  const MeshCheck c = check_mesh(united.mesh);
  EXPECT_EQ(c.boundary_edges, 0u);
  EXPECT_EQ(c.non_manifold_vertices, 0u);
  EXPECT_EQ(c.components, 2u);
  const auto alone = detail::unite(trunk, {crossing}, 1e-6 * 2.0);
  EXPECT_EQ(united.mesh.n_faces(), alone.mesh.n_faces() + away.n_faces());
  // The same up to the rounding of the piece apart to 32-bit floats.
  EXPECT_NEAR(c.volume, check_mesh(alone.mesh).volume + check_mesh(away).volume, 1e-7 * c.volume);
}

// A piece whose surface meets none of the tree's but holds it: the union is the piece alone (the
// tree is inside it), which corefinement finds.
TEST(MeshUnion, APieceHoldingTheTreeReplacesIt) {
  using P = TreeMesh::Point;
  const TreeMesh small = tetrahedron(P(0, 0, 0), P(1, 0, 0), P(0, 1, 0), P(0, 0, 1));
  const TreeMesh large = tetrahedron(P(-1, -1, -1), P(4, -1, -1), P(-1, 4, -1), P(-1, -1, 4));
  const auto united = detail::unite(small, {large}, 1e-9);
  EXPECT_EQ(united.united, 1u);
  EXPECT_EQ(united.mesh.n_faces(), 4u);
  EXPECT_NEAR(check_mesh(united.mesh).volume, check_mesh(large).volume, 1e-12);
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
