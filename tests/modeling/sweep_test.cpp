#include "model_fixtures.h"
#include "support/bundled.h"
#include "support/synthetic.h"
#include "treeskel/error.h"
#include "treeskel/eval/cylinders.h"
#include "treeskel/eval/paper_trees.h"
#include "treeskel/io/point_cloud_io.h"
#include "treeskel/modeling/radii.h"
#include "treeskel/modeling/coverage.h"
#include "treeskel/modeling/measurements.h"
#include "treeskel/modeling/sweep.h"
#include "treeskel/pipeline.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <set>

namespace treeskel::modeling {
namespace {

constexpr double kPi = 3.14159265358979323846;

void expect_valid(const TreeMesh& mesh) {
  const MeshCheck c = check_mesh(mesh);
  EXPECT_TRUE(c.ok()) << c.problem();
  EXPECT_EQ(c.boundary_edges, 0u);
  EXPECT_EQ(c.non_manifold_vertices, 0u);
  EXPECT_EQ(c.self_intersections, 0u);
  EXPECT_EQ(c.components, 1u);
  EXPECT_GT(c.volume, 0.0);
}

using test::bundled_skeleton;  // extracted once per ctest run (support/bundled.h)

TEST(SweepMesh, StraightBranchIsAClosedCylinderOfTheRightVolume) {
  const Skeleton s = test::straight(4.0, 0.05, 40);
  SweepStats stats;
  const TreeMesh mesh = sweep_mesh(s, {}, &stats);
  expect_valid(mesh);
  EXPECT_EQ(stats.branches, 1u);
  EXPECT_EQ(stats.junctions, 0u);
  // A cone of half a radius closes the tip; polygons keep the circle's area.
  const double expected = kPi * 0.05 * 0.05 * (4.0 - 0.025) + kPi * 0.05 * 0.05 * 0.025 / 3.0;
  EXPECT_NEAR(check_mesh(mesh).volume / expected, 1.0, 0.005);
  EXPECT_NEAR(check_mesh(mesh).volume / (kPi * 0.05 * 0.05 * 4.0), 1.0, 0.02);
}

/// Volume of the union of a Y's three cylinders by Monte Carlo (seeded; about 0.3% spread).
double union_volume(double trunk_radius, double half_angle) {
  const double r = trunk_radius / std::sqrt(2.0);
  std::vector<eval::Cylinder> parts{{Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 1), trunk_radius, trunk_radius}};
  for (double sign : {-1.0, 1.0})
    parts.push_back({Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(sign * std::sin(half_angle), 0, 1 + std::cos(half_angle)), r, r});
  const Eigen::Vector3d lo(-1.1, -0.06, -0.01), hi(1.1, 0.06, 2.01);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int samples = 2000000;
  int hits = 0;
  for (int i = 0; i < samples; ++i) {
    const Eigen::Vector3d p = lo + Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(hi - lo);
    for (const auto& c : parts)
      if (eval::inside(c, p)) {
        ++hits;
        break;
      }
  }
  return (hi - lo).prod() * hits / samples;
}

TEST(SweepMesh, YIsOneClosedMeshWithinTwoPercentOfItsVolume) {
  for (double half_angle : {0.35, 0.6, 1.0}) {
    const Skeleton s = test::y_shape(0.05, half_angle, 20);
    SweepStats stats;
    const TreeMesh mesh = sweep_mesh(s, {}, &stats);
    SCOPED_TRACE(half_angle);
    expect_valid(mesh);
    EXPECT_EQ(stats.junctions, 1u);
    EXPECT_NEAR(check_mesh(mesh).volume / union_volume(0.05, half_angle), 1.0, 0.02);
  }
}

/// A trunk standing at the origin with limbs leaving its base (the root is a fork), each limb
/// going to `to` with radius `limb_radius`.
Skeleton forked_base(const std::vector<Eigen::Vector3d>& limbs, double limb_radius) {
  Skeleton s;
  SkeletonNode root;
  root.position = Eigen::Vector3d::Zero();
  root.radius = 0.1;
  s.root = add_node(s, root);
  test::add_run(s, s.root, Eigen::Vector3d(0, 0, 3), 0.1, 30);
  for (const auto& to : limbs) test::add_run(s, s.root, to, limb_radius, 15);
  return s;
}

double lowest_z(const TreeMesh& mesh) {
  double z = 1e300;
  for (auto v : mesh.vertices()) z = std::min(z, static_cast<double>(mesh.point(v)[2]));
  return z;
}

// The join at a root with several branches is closed there by a flat base across the trunk, as a
// root with one branch is: the rings alone stood the tree on their hull, above its base.
TEST(SweepMesh, ATreeWhoseRootIsAForkStandsOnItsBase) {
  for (const auto& limbs : {std::vector<Eigen::Vector3d>{{1.5, 0, 1.5}},
                            std::vector<Eigen::Vector3d>{{1.5, 0, 1.5}, {-0.5, 1.0, 1.5}, {0, -1.5, 1.2}}}) {
    SCOPED_TRACE(limbs.size());
    const TreeMesh mesh = sweep_mesh(forked_base(limbs, 0.05), {});
    expect_valid(mesh);
    EXPECT_NEAR(lowest_z(mesh), 0.0, 1e-9);
    // The base is the trunk's: its widest points 0.1 from the axis, none below the root.
    std::size_t at_base = 0;
    for (auto v : mesh.vertices())
      if (std::abs(mesh.point(v)[2]) < 1e-9) {
        ++at_base;
        EXPECT_NEAR(std::hypot(mesh.point(v)[0], mesh.point(v)[1]), 0.1, 0.002);
      }
    EXPECT_GE(at_base, 6u);
  }
  // A limb leaving below the root's plane leaves no room for a base there: the rings close the
  // join as before, and the mesh is as valid.
  const TreeMesh low = sweep_mesh(forked_base({{1.5, 0, -0.3}}, 0.05), {});
  expect_valid(low);
  EXPECT_LT(lowest_z(low), 0.0);
}

// A fork grafted onto another at the same place makes a chain of no length between them, and a twig
// that never left its fork one more: neither has a ring, and the sweep stopped on them ("a branch of
// no length has no ring", seen on a completed AdTree tree33). The two forks are one join, the twig
// is the join's, and the mesh is the Y's with its third arm.
TEST(SweepMesh, ChainsOfNoLengthAreTheirJoins) {
  Skeleton s = test::y_shape(0.05, 0.6, 20);
  const NodeId fork = static_cast<NodeId>(20);
  ASSERT_EQ(boost::out_degree(fork, s.graph), 3u);
  SkeletonNode same = s[fork];
  same.points.clear();
  const NodeId twin = add_node(s, same);  // a second fork at the first one's place...
  boost::add_edge(fork, twin, s.graph);
  test::add_run(s, twin, Eigen::Vector3d(0, 0.8, 1.6), 0.02, 10);  // ... with an arm of its own
  const NodeId twig = add_node(s, same);
  boost::add_edge(twin, twig, s.graph);  // and a twig of no length
  ASSERT_TRUE(is_tree(s.graph));
  SweepStats stats;
  const TreeMesh mesh = sweep_mesh(s, {}, &stats);
  expect_valid(mesh);
  EXPECT_EQ(stats.junctions, 1u);
  EXPECT_GT(check_mesh(mesh).volume, union_volume(0.05, 0.6));
  double reach = 0.0;  // the third arm is there, to its tip
  for (auto v : mesh.vertices()) reach = std::max(reach, static_cast<double>(mesh.point(v)[1]));
  EXPECT_GT(reach, 0.8);
}

TEST(SweepMesh, PaperTreesGiveValidMeshes) {
  for (int index = 1; index <= 6; ++index) {
    Skeleton s = eval::make_paper_tree(index, 1).skeleton;
    fit_radii(s, nullptr);
    SweepStats stats;
    const TreeMesh mesh = sweep_mesh(s, {}, &stats);
    SCOPED_TRACE("tree " + std::to_string(index));
    expect_valid(mesh);
    EXPECT_GT(stats.branches, 10u);
    EXPECT_EQ(stats.late_repair_rounds, 0);  // the test of the parts found every crossing
  }
}

// Valid and whole: every branch of the skeleton is in the mesh. AdTree's tree1 has forks whose
// joins leave no room for a branch (the sweep once dropped them and showed 53% of the cloud):
// those are swept apart and united with the tree, and the mesh holds the skeleton's whole length.
TEST(SweepMesh, BundledCloudsGiveValidWholeMeshes) {
  // The cases below were found on tree1's skeleton of whole octree depths; today's default skeleton
  // of it must give a valid whole mesh too.
  for (const char* name : {"tree_rtwig.txt", "tree_adtree1.xyz", "tree_adtree1.xyz@whole-depths"}) {
    const Skeleton s = bundled_skeleton(name);
    SweepStats stats;
    const TreeMesh mesh = sweep_mesh(s, {}, &stats);
    SCOPED_TRACE(name);
    expect_valid(mesh);
    EXPECT_EQ(stats.pieces_failed, 0u);
    EXPECT_EQ(stats.pieces_apart, 0u);
    EXPECT_GE(skeleton_coverage(s, mesh).share(), 0.97);
    if (std::string(name) == "tree_adtree1.xyz@whole-depths") {
      EXPECT_GT(stats.pieces, 0u);
      // At 2.2 m the skeleton runs 0.24 m out between two forks of the stem and turns back by 111
      // degrees, within a few radii: no tube follows that, and the chain was thinned, with the
      // stem above it (6,834 nodes), to a third of its radius. It is swept straight instead.
      EXPECT_GE(stats.straightened_branches, 1u);
      // A twig may still be thinned once to clear a crossing (since the fits across the axis of
      // 7 December 2026: one of 5 mm carrying 0.05% of the wood, to 0.7 of its radius); the stem
      // was thinned three times, and the volume below would show it.
      EXPECT_LE(stats.repaired_shrunk, 1u);
      // Where the joins at both ends of a branch between two forks do not fit, the branch is swept
      // apart and united at its radii: thinned with all it carries (three times, at a cluster of
      // forks at 2.4 m), a 4 cm limb and the crown it bears kept 0.80 of the frustums' volume.
      EXPECT_EQ(stats.joins_thinned, 0u);
      EXPECT_GT(check_mesh(mesh).volume, 0.85 * measure_tree(s, nullptr).volume);
    }
    // The test of the parts catches the crossings, so CGAL's whole-mesh test starts no round (the
    // limbs swept apart on AdTree's cloud, counted here too, may need one).
    EXPECT_LE(stats.late_repair_rounds, std::string(name) == "tree_rtwig.txt" ? 0 : 1);
  }
}

// Every mesh format stores 32-bit floats: distinct vertices must stay distinct there, or the saved
// mesh is no longer manifold (AdTree's cloud gives twigs a millionth of the trunk's radius).
TEST(SweepMesh, BundledCloudsKeepTheirVerticesApartInFloat) {
  for (const char* name : {"tree_rtwig.txt", "tree_adtree1.xyz"}) {
    const Skeleton s = bundled_skeleton(name);
    SweepStats stats;
    const TreeMesh mesh = sweep_mesh(s, {}, &stats);
    std::set<std::array<float, 3>> seen;
    for (const auto v : mesh.vertices()) {
      const auto& p = mesh.point(v);
      const Eigen::Vector3d w = Eigen::Vector3d(p[0], p[1], p[2]) + s.offset;
      EXPECT_TRUE(seen.insert({float(w.x()), float(w.y()), float(w.z())}).second) << name << ": vertex " << v.idx();
    }
    // Such twigs are raised to the floor radius, not left out.
    EXPECT_EQ(stats.thin_left_out, 0u) << name;
  }
}

// glTF files (and every format with `model --local`) hold the local frame's floats: with
// `local_floats` the united mesh is rounded to those floats and tested there, so the file holds the
// mesh that was checked. By default it is rounded in the input's frame, whose floats differ.
TEST(SweepMesh, LocalFloatsAreTheFloatsTheMeshIsRoundedTo) {
  const Skeleton s = bundled_skeleton("tree_adtree1.xyz");
  ASSERT_GT(s.offset.norm(), 1.0);  // the cloud is recentred: the two frames' floats differ
  auto float_exact = [](const TreeMesh& mesh) {
    std::size_t exact = 0;
    for (const auto v : mesh.vertices()) {
      const auto& p = mesh.point(v);
      exact += double(float(p[0])) == p[0] && double(float(p[1])) == p[1] && double(float(p[2])) == p[2];
    }
    return exact;
  };
  SweepOptions local;
  local.local_floats = true;
  SweepStats stats;
  const TreeMesh mesh = sweep_mesh(s, local, &stats);
  ASSERT_GT(stats.pieces, 0u);  // the union ran, and rounded every vertex
  expect_valid(mesh);
  EXPECT_EQ(float_exact(mesh), mesh.n_vertices());
  std::vector<TreeMesh::Point> floats;
  for (const auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    floats.emplace_back(float(p[0]), float(p[1]), float(p[2]));
  }
  EXPECT_TRUE(self_intersecting_faces_at(mesh, floats).empty());
  const TreeMesh input_frame = sweep_mesh(s, {});
  EXPECT_LT(float_exact(input_frame), input_frame.n_vertices() / 2);
  std::size_t world_exact = 0;
  for (const auto v : input_frame.vertices()) {
    const auto& p = input_frame.point(v);
    const double w = p[0] + s.offset.x();
    world_exact += double(float(w)) == w;
  }
  EXPECT_EQ(world_exact, input_frame.n_vertices());
}

/// A trunk with two forks; from the low fork a branch rising gently along x (radius 0.05), from the
/// high one a thinner branch (0.04) coming down onto it, whose last part comes within 0.075 of it
/// (their radii sum to 0.09). The descending branch holds about a tenth of the skeleton's wood.
Skeleton crossing_branches() {
  Skeleton s = test::straight(1.0, 0.1, 10);
  const NodeId low_fork = static_cast<NodeId>(s.node_count() - 1);
  const NodeId high_fork = test::add_run(s, low_fork, Eigen::Vector3d(0, 0, 2), 0.08, 10);
  test::add_run(s, high_fork, Eigen::Vector3d(0, 0, 2.8), 0.05, 8);
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
  return s;
}

// Two branches from different forks whose tubes run through each other: the repair thins the
// thinner one (by what clears it, not step by step) until the mesh no longer intersects itself.
TEST(SweepMesh, CrossingBranchesAreThinnedUntilTheyClear) {
  const Skeleton s = crossing_branches();
  SweepOptions no_repair;
  no_repair.repair = false;
  EXPECT_GT(check_mesh(sweep_mesh(s, no_repair)).self_intersections, 0u);  // they do cross

  SweepOptions o;
  o.max_thinned_share = 0.5;  // the thinner branch carries less: it is thinned
  SweepStats stats;
  const TreeMesh mesh = sweep_mesh(s, o, &stats);
  expect_valid(mesh);
  EXPECT_EQ(stats.self_intersections, 0u);
  EXPECT_GE(stats.repair_rounds, 1);
  EXPECT_EQ(stats.attempts, 2);  // one round: x0.7 a round would have taken two
  EXPECT_EQ(stats.late_repair_rounds, 0);
  EXPECT_EQ(stats.repaired_dropped, 0u);
  EXPECT_GE(stats.repaired_shrunk, 1u);
}

TEST(SweepMesh, ABranchThatCarriesMuchOfTheWoodIsSweptApartNotThinned) {
  // By default a branch that carries 2% of the wood or more is not thinned (with all it carries)
  // where it crosses another: it is swept apart at its own radius and united with the tree.
  const Skeleton s = crossing_branches();
  SweepStats stats;
  const TreeMesh mesh = sweep_mesh(s, {}, &stats);
  expect_valid(mesh);
  EXPECT_EQ(check_mesh(mesh).components, 1u);
  EXPECT_EQ(stats.self_intersections, 0u);
  EXPECT_EQ(stats.repaired_shrunk, 0u);
  EXPECT_EQ(stats.repaired_dropped, 1u);
  EXPECT_GE(stats.pieces, 1u);
  EXPECT_EQ(stats.pieces_apart, 0u);
  // The descending branch keeps its radius: a line along its last run, 0.9 of its radius to the side
  // (+y, away from the other branch), lies inside the mesh. Thinned by 0.7 it would lie outside.
  Skeleton side;
  SkeletonNode from, to;
  from.position = Eigen::Vector3d(0.5, 0.9 * 0.04, 1.5 - (1.5 - 1.315) * 0.2 / 0.9);
  to.position = Eigen::Vector3d(1.0, 0.9 * 0.04, 1.5 - (1.5 - 1.315) * 0.7 / 0.9);
  const NodeId f = add_node(side, from), t = add_node(side, to);
  boost::add_edge(f, t, side.graph);
  side.root = f;
  EXPECT_GT(skeleton_coverage(side, mesh).share(), 0.99);
}

TEST(SweepMesh, ATrunkWhoseSkeletonWandersInsideItIsNotThinned) {
  // The pattern of a synthetic tree's trunk (tree4 at 8375 points): the medians run 0.8 radii out
  // across the trunk and back, then step down 0.7 radii and up again. Swept through every node, the
  // tube crossed itself and the repair thinned the trunk, and all it carries, to a fifth of its volume.
  const double r = 0.027;
  Skeleton s = test::straight(0.11, r, 28);
  NodeId at = static_cast<NodeId>(s.node_count() - 1);
  at = test::add_run(s, at, Eigen::Vector3d(-0.021, 0.018, 0.114), r, 6);
  at = test::add_run(s, at, Eigen::Vector3d(0.013, 0.009, 0.110), r, 6);
  at = test::add_run(s, at, Eigen::Vector3d(0.0, 0.0, 0.162), r, 6);
  at = test::add_run(s, at, Eigen::Vector3d(0.0, 0.0, 0.144), r, 5);
  test::add_run(s, at, Eigen::Vector3d(0.0, 0.0, 0.6), r, 100);
  SweepStats stats;
  const TreeMesh mesh = sweep_mesh(s, {}, &stats);
  expect_valid(mesh);
  EXPECT_EQ(stats.repaired_shrunk, 0u);
  EXPECT_EQ(stats.late_repair_rounds, 0);
  // About the volume of a straight trunk as tall (the excursions add a little length).
  EXPECT_NEAR(check_mesh(mesh).volume / (kPi * r * r * 0.6), 1.0, 0.1);
}

// Where the trunk's skeleton zigzags through forks a centimetre or two apart near the base (two of
// the synthetic clouds whose density falls with height), parts of the trunk on both sides of a fork
// crossed, and the repair thinned the part above, with all it carries: the whole tree, to an
// eighth of its radius (meshes of 2% and 22% of the wood volume). The forks between two crossing
// parts of one line are made one join instead. (The limbs' straightening, on by default since,
// takes these folds out; the skeleton here keeps its path, as a saved skeleton modelled with
// --stiffness 0 would.)
TEST(SweepMesh, AFoldOfTheTrunkAtCloseForksMakesOneJoinNotAThinTree) {
  for (const int index : {3, 4}) {
    const eval::GroundTruth truth = eval::make_paper_tree(index, 1);
    for (const auto& c : eval::make_paper_clouds(truth, index, 1)) {
      if (c.name != (index == 3 ? "tree3_vdensity_2" : "tree4_vdensity_1")) continue;
      SCOPED_TRACE(c.name);
      Skeleton s = extract_skeleton(c.cloud);
      RadiusOptions kept_path;
      kept_path.stiffness = 0.0;
      fit_radii(s, &c.cloud, kept_path);
      SweepStats stats;
      const TreeMesh mesh = sweep_mesh(s, {}, &stats);
      expect_valid(mesh);
      EXPECT_GE(stats.merged_forks, 1u);
      EXPECT_GT(check_mesh(mesh).volume, 0.5 * measure_tree(s, nullptr).volume);
    }
  }
}

TEST(SweepMesh, ThinBranchesCanBeLeftOut) {
  const Skeleton s = test::y_shape(0.05, 0.6, 20);
  SweepOptions o;
  o.min_radius = 0.04;  // the arms are 0.035
  SweepStats stats;
  const TreeMesh mesh = sweep_mesh(s, o, &stats);
  EXPECT_EQ(stats.thin_left_out, 2u);
  expect_valid(mesh);
  EXPECT_LT(check_mesh(mesh).volume, 0.6 * kPi * 0.05 * 0.05 * 2.0);
}

// A twig far thinner than the tree's extent allows is raised to a ten-thousandth of the extent
// (and to a thousandth of the trunk's radius when that is more): its tube keeps its shape in floats.
TEST(SweepMesh, TwigsAreRaisedToTheFloorOfTheExtent) {
  Skeleton s = test::straight(10.0, 0.1, 20);
  const NodeId from = 10;  // z = 5
  const NodeId first = s.node_count();
  const NodeId tip = test::add_run(s, from, Eigen::Vector3d(1.0, 0.0, 6.0), 1e-6, 10);
  for (NodeId v = first; v < s.node_count(); ++v) s[v].radius = 1e-6;
  // The farthest a vertex halfway along the twig lies from its axis (the trunk's are 0.1 or more away).
  auto twig_radius = [&](const TreeMesh& mesh) {
    const Eigen::Vector3d a = s[from].position, b = s[tip].position, d = (b - a).normalized();
    double r = 0.0;
    for (auto v : mesh.vertices()) {
      const auto p = mesh.point(v);
      const Eigen::Vector3d q(p[0], p[1], p[2]);
      const double t = (q - a).dot(d);
      const double off = (q - a - t * d).norm();
      if (std::abs(t - 0.5 * (b - a).norm()) < 0.2 && off < 0.01) r = std::max(r, off);
    }
    return r;
  };
  SweepStats stats;
  const TreeMesh mesh = sweep_mesh(s, {}, &stats);
  expect_valid(mesh);
  EXPECT_EQ(stats.raised_to_floor, 10u);
  EXPECT_GT(twig_radius(mesh), 0.9e-3);  // 1e-4 of the 10 m extent
  EXPECT_LT(twig_radius(mesh), 1.2e-3);
  SweepOptions relative_only;
  relative_only.min_extent_radius = 0.0;
  const TreeMesh thin = sweep_mesh(s, relative_only);
  EXPECT_GT(twig_radius(thin), 0.9e-4);  // 1e-3 of the trunk's 0.1
  EXPECT_LT(twig_radius(thin), 1.2e-4);
}

/// The heights of the rings of a vertical tube's mesh (its vertices' distinct z, the caps' centres
/// and the tip's apex left out: the vertices off the axis).
std::vector<double> ring_heights(const TreeMesh& mesh) {
  std::set<double> z;
  for (auto v : mesh.vertices()) {
    const auto p = mesh.point(v);
    if (std::hypot(p[0], p[1]) > 1e-9) z.insert(p[2]);
  }
  return {z.begin(), z.end()};
}

// A straight, evenly thick run is one tube whose rings are as far apart as a band may be long, 2%
// of the tree's extent, not a ring at each of its nodes (here 2 cm apart, each 2 radii from the
// last: the old rule of a ring every 0.75 radii laid 501).
TEST(SweepMesh, AStraightRunHasARingOnlyWhereABandWouldGrowTooLong) {
  const Skeleton s = test::straight(10.0, 0.01, 500);
  const TreeMesh mesh = sweep_mesh(s);
  expect_valid(mesh);
  const auto z = ring_heights(mesh);
  ASSERT_GE(z.size(), 2u);
  double longest = 0.0;
  for (std::size_t i = 1; i < z.size(); ++i) longest = std::max(longest, z[i] - z[i - 1]);
  EXPECT_LE(longest, 0.2 + 1e-9);
  EXPECT_GT(longest, 0.15);
  EXPECT_LE(z.size(), 55u);
  EXPECT_GE(z.size(), 50u);
}

// Where the skeleton zigzags by more than half its radius between nodes, each node keeps its
// ring and the skeleton stays inside the tube; by less, the tube runs straight past nodes (here
// until a band would be longer than 2% of the extent: every other node), and the skeleton is
// still inside.
TEST(SweepMesh, ATubeLeavesOutOnlyTheRingsItsSkeletonStaysInsideWithout) {
  constexpr int kNodes = 120;  // 1.19 m: a band may be 2.38 cm long
  auto zigzag = [](double amplitude) {
    Skeleton s;
    SkeletonNode root;
    root.radius = 0.002;
    s.root = add_node(s, root);
    NodeId prev = s.root;
    for (int i = 1; i < kNodes; ++i) {  // nodes 1 cm (5 radii) apart, every other one off the axis
      SkeletonNode node;
      node.position = Eigen::Vector3d(i % 2 ? amplitude : 0.0, 0.0, 0.01 * i);
      node.radius = 0.002;
      const NodeId v = add_node(s, node);
      boost::add_edge(prev, v, s.graph);
      prev = v;
    }
    return s;
  };
  for (const double amplitude : {0.0012, 0.0006}) {
    SCOPED_TRACE(amplitude);
    const Skeleton s = zigzag(amplitude);
    const TreeMesh mesh = sweep_mesh(s);
    expect_valid(mesh);
    EXPECT_GT(skeleton_coverage(s, mesh).share(), 0.999);
    // The rings: 24 vertices each (the trunk's sides), besides the base's centre and the tip's apex.
    const std::size_t rings = (mesh.n_vertices() - 2) / 24;
    EXPECT_EQ(mesh.n_vertices(), 24 * rings + 2);
    if (amplitude > 0.001) EXPECT_GE(rings, kNodes - 2u);  // one at each node but the last (the tip's)
    else EXPECT_LE(rings, kNodes / 2 + 2u);
  }
}

TEST(SweepMesh, SegmentsFollowTheRadius) {
  const TreeMesh thick = sweep_mesh(test::straight(1.0, 0.1, 10));
  SweepOptions o;
  o.trunk_segments = 12;
  const TreeMesh coarse = sweep_mesh(test::straight(1.0, 0.1, 10), o);
  EXPECT_LT(coarse.n_faces(), thick.n_faces());
}

TEST(SweepMesh, RefusesBadSkeletons) {
  EXPECT_THROW(sweep_mesh(Skeleton{}), InputError);
  Skeleton lone;
  SkeletonNode n;
  n.radius = 1.0;
  add_node(lone, n);
  EXPECT_THROW(sweep_mesh(lone), InputError);
  Skeleton zero = test::straight(1.0, 0.1, 4);
  zero[2].radius = 0.0;
  EXPECT_THROW(sweep_mesh(zero), InputError);
  Skeleton negative = test::straight(1.0, -0.1, 4);
  EXPECT_THROW(sweep_mesh(negative), InputError);
  Skeleton cycle = test::straight(1.0, 0.1, 4);
  boost::add_edge(0, 4, cycle.graph);
  EXPECT_THROW(sweep_mesh(cycle), InputError);
  SweepOptions o;
  o.min_segments = 2;
  EXPECT_THROW(sweep_mesh(test::straight(1.0, 0.1, 4), o), OptionError);
}

}  // namespace
}  // namespace treeskel::modeling

namespace treeskel::modeling {
namespace {

TEST(SweepMesh, SameSkeletonSameMesh) {
  const Skeleton s = bundled_skeleton("tree_adtree1.xyz");
  const TreeMesh a = sweep_mesh(s), b = sweep_mesh(s);
  ASSERT_EQ(a.n_vertices(), b.n_vertices());
  ASSERT_EQ(a.n_faces(), b.n_faces());
  for (auto v : a.vertices()) ASSERT_EQ(a.point(v), b.point(v)) << v.idx();
  for (auto f : a.faces()) {
    std::vector<int> fa, fb;
    for (auto v : a.fv_range(f)) fa.push_back(v.idx());
    for (auto v : b.fv_range(b.face_handle(static_cast<unsigned>(f.idx())))) fb.push_back(v.idx());
    ASSERT_EQ(fa, fb) << f.idx();
  }
}

}  // namespace
}  // namespace treeskel::modeling
