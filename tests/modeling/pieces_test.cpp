// The limbs swept apart and united with the tree (modeling/src/pieces.h, private to the library).
#include "../../modeling/src/pieces.h"
#include "../../modeling/src/skeleton_parts.h"
#include "model_fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

namespace treeskel::modeling::detail {
namespace {

// test::y_shape(r, half_angle, 20): nodes 0..20 the trunk (20 the fork), 21..40 one arm, 41..60 the other.

std::size_t tips(const Skeleton& s) {
  std::size_t n = 0;
  for (NodeId v = 0; v < s.node_count(); ++v) n += (v != s.root && boost::out_degree(v, s.graph) == 1);
  return n;
}

TEST(Pieces, APathSplitsIntoTwoOverlappingHalves) {
  const Skeleton path = test::straight(1.0, 0.1, 6);  // 7 nodes
  const auto parts = split_piece(path);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[0].node_count(), 4u);  // nodes 0..3
  EXPECT_EQ(parts[1].node_count(), 5u);  // nodes 2..6: they share the segment 2-3
  EXPECT_EQ(parts[0][0].position, path[0].position);
  EXPECT_EQ(parts[1][parts[1].node_count() - 1].position, path[6].position);
  EXPECT_EQ(parts[1][0].position, path[2].position);
}

TEST(Pieces, ASingleSegmentCannotBeSplit) {
  EXPECT_TRUE(split_piece(test::straight(1.0, 0.1, 1)).empty());
}

// A fork: each arm apart (from the fork, with a stub back along the trunk) and the trunk in halves.
TEST(Pieces, AForkSplitsIntoItsArmsAndTheHalvesOfItsBase) {
  const Skeleton y = test::y_shape(0.05, 0.6, 20);
  const auto parts = split_piece(y);
  ASSERT_EQ(parts.size(), 4u);
  std::size_t arm_tips = 0;
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_TRUE(is_tree(parts[i].graph));
    EXPECT_EQ(tips(parts[i]), 1u);
    arm_tips += tips(parts[i]);
    EXPECT_GE(parts[i].node_count(), 21u);  // the arm, its fork and the stub
  }
  EXPECT_EQ(arm_tips, 2u);
  EXPECT_EQ(parts[2].node_count() + parts[3].node_count(), 21u + 2u);  // the trunk, two nodes shared
}

// A fork over a base of two segments: the arms apart and the base whole. Halved, the base's halves
// would share only its middle node, and the arms' stubs would go into a half that meets nothing.
TEST(Pieces, AShortBaseUnderAForkStaysWhole) {
  Skeleton s = test::straight(0.2, 0.05, 2);  // 3 nodes: root, middle, fork
  const NodeId fork = static_cast<NodeId>(s.node_count() - 1);
  test::add_run(s, fork, Eigen::Vector3d(0.3, 0, 0.6), 0.02, 10);
  test::add_run(s, fork, Eigen::Vector3d(-0.3, 0, 0.6), 0.02, 10);
  const auto parts = split_piece(s);
  ASSERT_EQ(parts.size(), 3u);  // two arms and the base
  const Skeleton& base = parts.back();
  EXPECT_EQ(base.node_count(), 3u);
  EXPECT_EQ(base[0].position, s[s.root].position);
  EXPECT_EQ(base[2].position, s[fork].position);
  for (const auto& part : parts) EXPECT_LT(part.node_count(), s.node_count());
  // A bare path of two segments still splits in two: nothing else would make it smaller.
  EXPECT_EQ(split_piece(test::straight(0.2, 0.05, 2)).size(), 2u);
}

// Splitting goes on until single segments: every part is smaller than what it came from.
TEST(Pieces, SplittingEnds) {
  std::vector<Skeleton> todo{test::y_shape(0.05, 0.6, 20)};
  std::size_t segments = 0, rounds = 0;
  while (!todo.empty() && ++rounds < 10000) {
    Skeleton s = std::move(todo.back());
    todo.pop_back();
    auto parts = split_piece(s);
    if (parts.empty()) {
      EXPECT_EQ(s.node_count(), 2u);
      ++segments;
    }
    for (auto& p : parts) {
      EXPECT_LT(p.node_count(), s.node_count());
      todo.push_back(std::move(p));
    }
  }
  EXPECT_TRUE(todo.empty());
  EXPECT_GT(segments, 20u);
}

// A piece split after its sweep was counted (its union crossed itself) has its parts swept and
// counted again: what it put into the mesh is taken back, the work it took is not, and no count
// goes below zero. (Split pieces once made the report give 5,600 branches for a tree of 1,200.)
TEST(Pieces, ASplitPiecesCountsAreTakenBackButNotItsWork) {
  SweepStats tree;
  tree.branches = 40;
  tree.junctions = 18;
  tree.joins_dropped = 2;
  tree.attempts = 3;
  SweepStats piece;
  piece.branches = 7;
  piece.junctions = 3;
  piece.merged_forks = 1;
  piece.relocated_branches = 2;
  piece.repaired_shrunk = 1;
  piece.attempts = 2;
  piece.repair_rounds = 1;
  add_counts(tree, piece);
  EXPECT_EQ(tree.branches, 47u);
  EXPECT_EQ(tree.attempts, 5);
  take_counts(tree, piece);
  EXPECT_EQ(tree.branches, 40u);
  EXPECT_EQ(tree.junctions, 18u);
  EXPECT_EQ(tree.merged_forks, 0u);
  EXPECT_EQ(tree.relocated_branches, 0u);
  EXPECT_EQ(tree.repaired_shrunk, 0u);
  EXPECT_EQ(tree.joins_dropped, 2u);
  EXPECT_EQ(tree.attempts, 5);  // the sweeps were run
  EXPECT_EQ(tree.repair_rounds, 1);
  SweepStats none;
  take_counts(none, piece);
  EXPECT_EQ(none.branches, 0u);
  EXPECT_EQ(none.junctions, 0u);
}

// faces_touching hashes the boxes into a grid (boxes over many cells kept aside): it must find what
// testing every face against every box finds, for small, flat, large and no boxes.
TEST(Pieces, FacesTouchingBoxesAsTestingEachPair) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> at(0.0, 10.0), step(-0.3, 0.3);
  TreeMesh m;
  for (int i = 0; i < 400; ++i) {
    const TreeMesh::Point o(at(rng), at(rng), at(rng));
    const auto a = m.add_vertex(o), b = m.add_vertex(o + TreeMesh::Point(step(rng), step(rng), step(rng))),
               c = m.add_vertex(o + TreeMesh::Point(step(rng), step(rng), step(rng)));
    m.add_face(a, b, c);
  }
  auto box = [](Eigen::Vector3d lo, Eigen::Vector3d size) { return Eigen::AlignedBox3d(lo, lo + size); };
  std::vector<Eigen::AlignedBox3d> boxes;
  std::uniform_real_distribution<double> side(0.0, 0.5);
  for (int i = 0; i < 30; ++i)
    boxes.push_back(box({at(rng), at(rng), at(rng)}, {side(rng), side(rng), side(rng)}));
  boxes.push_back(box({at(rng), at(rng), 5.0}, {0.4, 0.4, 0.0}));  // flat
  auto brute = [&](const std::vector<Eigen::AlignedBox3d>& bs) {
    std::vector<std::size_t> out;
    for (auto f : m.faces()) {
      Eigen::AlignedBox3d fb;
      for (auto v : m.fv_range(f)) fb.extend(Eigen::Vector3d(m.point(v)[0], m.point(v)[1], m.point(v)[2]));
      if (std::any_of(bs.begin(), bs.end(), [&](const auto& b) { return b.intersects(fb); }))
        out.push_back(static_cast<std::size_t>(f.idx()));
    }
    return out;
  };
  const auto small = faces_touching(m, boxes);
  EXPECT_FALSE(small.empty());
  EXPECT_EQ(small, brute(boxes));
  boxes.push_back(box({2.0, 0.0, 0.0}, {3.0, 10.0, 10.0}));  // over many cells: kept aside
  const auto large = faces_touching(m, boxes);
  EXPECT_GT(large.size(), small.size());
  EXPECT_EQ(large, brute(boxes));
  EXPECT_TRUE(faces_touching(m, {}).empty());
  // Boxes of many sizes (each goes to the grid of its size) and long faces (queries over many cells).
  std::uniform_real_distribution<double> scale(-3.0, 0.7);
  std::vector<Eigen::AlignedBox3d> mixed;
  for (int i = 0; i < 60; ++i) {
    const double s = std::pow(10.0, scale(rng));
    mixed.push_back(box({at(rng), at(rng), at(rng)}, {s * side(rng), s, s * side(rng)}));
  }
  for (int i = 0; i < 40; ++i) {
    const TreeMesh::Point o(at(rng), at(rng), at(rng));
    const auto a = m.add_vertex(o), b = m.add_vertex(o + TreeMesh::Point(6.0 * step(rng), 0.01, 0.0)),
               c = m.add_vertex(o + TreeMesh::Point(0.0, 0.01, 8.0 * step(rng)));
    m.add_face(a, b, c);
  }
  const auto found = faces_touching(m, mixed);
  EXPECT_GT(found.size(), 10u);
  EXPECT_EQ(found, brute(mixed));
  mixed.push_back(box({-1e6, 4.0, -1e6}, {2e6, 0.1, 2e6}));  // a slab over the whole mesh
  EXPECT_EQ(faces_touching(m, mixed), brute(mixed));
}

TEST(Pieces, FloatsOfTheFrame) {
  TreeMesh m;
  m.add_vertex(TreeMesh::Point(0.1, 0.2, 0.3));
  const Eigen::Vector3d offset(500000.0, 0.0, 0.0);
  const auto f = world_floats(m, offset);
  ASSERT_EQ(f.size(), 1u);
  const auto p = f[0];
  EXPECT_EQ(p[0], static_cast<double>(static_cast<float>(500000.1)));  // floats are 1/32 apart there
  EXPECT_EQ(p[1], static_cast<double>(0.2f));
}

// Files hold the input's frame unless 32-bit floats would round it: a georeferenced tree is local.
TEST(Pieces, FileFrameIsLocalOnlyWhereFloatsWouldRoundTheTree) {
  Skeleton s = test::straight(10.0, 0.1, 10);
  s.offset = Eigen::Vector3d(3.0, -2.0, 1.0);
  EXPECT_EQ(file_frame(s), s.offset);
  s.offset = Eigen::Vector3d(600000.0, 5200000.0, 300.0);
  EXPECT_EQ(file_frame(s), Eigen::Vector3d::Zero());
}

// A piece of a tree tells its limbs by the whole tree's trunk (TreeScale::limb_radius), not by its
// own thickest branch: two branches whose axes cross cannot be cleared by thinning, and the thinner
// one goes apart after a twig's thinnings when the tree's trunk is far thicker than the piece, after
// a limb's when it is not.
TEST(Pieces, APieceTellsItsLimbsByTheWholeTree) {
  Skeleton s = test::straight(1.0, 0.1, 10);
  const NodeId low = static_cast<NodeId>(s.node_count() - 1);
  const NodeId high = test::add_run(s, low, Eigen::Vector3d(0, 0, 2), 0.1, 10);
  test::add_run(s, high, Eigen::Vector3d(0, 0, 2.6), 0.08, 6);
  test::add_run(s, low, Eigen::Vector3d(1.5, 0, 1.0), 0.05, 15);
  test::add_run(s, high, Eigen::Vector3d(1.0, 0, 0.5), 0.04, 15);  // through the first one's axis
  const SweepOptions o;
  std::array<std::size_t, 2> thinned{};
  for (const int whole : {0, 1}) {
    SCOPED_TRACE(whole);
    const double trunk = whole ? 1.0 : 0.1;  // the piece's own trunk, or a tree's ten times thicker
    SweepStats st;
    std::vector<Skeleton> apart;
    const TreeMesh mesh = sweep_part(s, o, Eigen::Vector3d::Zero(), {1e-4, o.max_drop_radius * trunk}, st, apart, nullptr);
    EXPECT_GT(mesh.n_faces(), 0u);
    EXPECT_EQ(st.self_intersections, 0u);
    EXPECT_EQ(st.repaired_dropped, 1u);
    ASSERT_EQ(apart.size(), 1u);
    EXPECT_NEAR(apart.front()[apart.front().root].position.z(), 2.0, 0.11);  // from the high fork
    thinned[static_cast<std::size_t>(whole)] = st.repaired_shrunk;
  }
  EXPECT_GT(thinned[0], static_cast<std::size_t>(o.max_shrinks));   // a limb of its piece
  EXPECT_LE(thinned[1], static_cast<std::size_t>(o.max_shrinks));   // a twig of the tree
}

// Two limbs swept apart from one fork start at one point of their parent's path (piece_of): with
// flat base caps their discs lie in one plane and overlap, which corefinement works through in exact
// numbers; a piece's base (BaseCap::hidden) is a shallow cone into its tube, aside toward where its
// limb goes, so the two share no face's plane. Each piece stays closed and free of crossings.
TEST(Pieces, SiblingPiecesShareNoBasePlane) {
  const Skeleton y = test::y_shape(0.05, 0.6, 20);
  const ChainTree tree = build_chains(y);
  const Skeleton a = piece_of(y, tree, 21), b = piece_of(y, tree, 41);
  ASSERT_LT((a[a.root].position - b[b.root].position).norm(), 1e-12);  // one start
  auto sweep = [](const Skeleton& s, BaseCap cap) {
    SweepStats st;
    std::vector<Skeleton> apart;
    TreeMesh mesh = sweep_part(s, SweepOptions{}, Eigen::Vector3d::Zero(), {1e-4, 1.0}, st, apart, nullptr, cap);
    EXPECT_EQ(st.self_intersections, 0u);
    EXPECT_TRUE(apart.empty());
    const MeshCheck check = check_mesh(mesh, true);
    EXPECT_TRUE(check.ok()) << check.problem();
    return mesh;
  };
  // Faces of the base cap of `p` (across the stub's axis, at its end) that lie in the plane of a face
  // of `q` (to 5e-11). (Their stubs' walls are one tube here, both arms as thick: not counted.)
  auto shared_planes = [&](const TreeMesh& p, const TreeMesh& q) {
    const Eigen::Vector3d start = a[a.root].position;
    const Eigen::Vector3d axis = (a[*boost::adjacent_vertices(a.root, a.graph).first].position - start).normalized();
    auto corners = [](const TreeMesh& m, TreeMesh::FaceHandle f) {
      std::array<Eigen::Vector3d, 3> c;
      std::size_t k = 0;
      for (auto v : m.fv_range(f)) {
        const auto x = m.point(v);
        c[k++] = Eigen::Vector3d(x[0], x[1], x[2]);
      }
      return c;
    };
    std::size_t count = 0;
    for (auto f : p.faces()) {
      const auto c = corners(p, f);
      if ((c[0] - start).norm() > 0.1) continue;
      const Eigen::Vector3d n = (c[1] - c[0]).cross(c[2] - c[0]).normalized();
      if (std::abs(n.dot(axis)) < 0.5) continue;  // a wall's face
      for (auto g : q.faces()) {
        const auto d = corners(q, g);
        if ((d[0] - start).norm() > 0.1) continue;
        if (std::all_of(d.begin(), d.end(), [&](const Eigen::Vector3d& x) { return std::abs(n.dot(x - c[0])) < 5e-11; })) ++count;
      }
    }
    return count;
  };
  EXPECT_GT(shared_planes(sweep(a, BaseCap::flat), sweep(b, BaseCap::flat)), 0u);
  const TreeMesh hidden_a = sweep(a, BaseCap::hidden), hidden_b = sweep(b, BaseCap::hidden);
  EXPECT_EQ(shared_planes(hidden_a, hidden_b), 0u);
  // The cone goes into the tube: a little less wood than the flat cap's.
  const double flat = check_mesh(sweep(a, BaseCap::flat), false).volume, cone = check_mesh(hidden_a, false).volume;
  EXPECT_LT(cone, flat);
  EXPECT_GT(cone, 0.97 * flat);
}

}  // namespace
}  // namespace treeskel::modeling::detail
