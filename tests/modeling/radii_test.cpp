#include "model_fixtures.h"
#include "treeskel/error.h"
#include "treeskel/eval/cylinders.h"
#include "treeskel/eval/paper_trees.h"
#include "treeskel/modeling/chains.h"
#include "treeskel/modeling/radii.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace treeskel::modeling {
namespace {

/// r(fork)^e = sum of r(child)^e at every fork, to `tolerance` relative; radii never grow toward
/// the tips.
void expect_pipe_model(const Skeleton& s, double e, double tolerance = 1e-6) {
  const ChainTree t = build_chains(s);
  std::size_t forks = 0;
  for (NodeId v = 0; v < s.node_count(); ++v) {
    ASSERT_GT(s[v].radius, 0.0) << v;
    for (NodeId c : t.children[v]) EXPECT_LE(s[c].radius, s[v].radius * (1.0 + 1e-12)) << v << " -> " << c;
    if (t.children[v].size() < 2) continue;
    ++forks;
    double sum = 0.0;
    for (NodeId c : t.children[v]) sum += std::pow(s[c].radius, e);
    EXPECT_NEAR(sum / std::pow(s[v].radius, e), 1.0, tolerance) << "fork " << v;
  }
  EXPECT_GT(forks, 0u);
}

TEST(FitCircle, ExactCircleFewPointsAndALine) {
  std::vector<Eigen::Vector2d> q;
  for (int k = 0; k < 7; ++k) q.emplace_back(3.0 + 2.0 * std::cos(0.4 * k), -1.0 + 2.0 * std::sin(0.4 * k));
  const CircleFit fit = fit_circle(q);
  EXPECT_NEAR(fit.radius, 2.0, 1e-9);
  EXPECT_NEAR(fit.centre.x(), 3.0, 1e-9);
  EXPECT_NEAR(fit.centre.y(), -1.0, 1e-9);
  EXPECT_NEAR(fit.rms, 0.0, 1e-9);
  EXPECT_NEAR(fit.coverage, 2.4, 1e-9);  // 7 points 0.4 rad apart
  EXPECT_TRUE(is_reliable(fit, {}));
  RadiusOptions wider;
  wider.min_coverage = 3.0;
  EXPECT_FALSE(is_reliable(fit, wider));
  EXPECT_FALSE(is_reliable(CircleFit{}, {}));
  EXPECT_EQ(fit_circle({q[0], q[1]}).radius, 0.0);
  EXPECT_EQ(fit_circle({Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), Eigen::Vector2d(2, 2), Eigen::Vector2d(3, 3)}).radius, 0.0);
}

TEST(MeasureNodeRadii, CircleFitRecoversAHalfScannedBranch) {
  // One scanner sees only the +x half of a branch of radius 0.1; the nodes sit off-axis toward
  // the scanned side, as L1-medians of such a half do.
  eval::SurfaceSampling sampling;
  sampling.points = 4000;
  sampling.facing = Eigen::Vector3d::UnitX();
  const PointCloud cloud = eval::sample_cylinders({{Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 1), 0.1, 0.1}}, sampling);
  Skeleton s;
  for (int i = 0; i <= 10; ++i) {
    SkeletonNode node;
    node.position = Eigen::Vector3d(0.06, 0.0, 0.1 * i);
    const NodeId v = add_node(s, node);
    if (i > 0) boost::add_edge(v - 1, v, s.graph);
  }
  for (std::uint32_t i = 0; i < cloud.size(); ++i) {
    const auto k = static_cast<NodeId>(std::lround(std::clamp((cloud.positions[i].z() + cloud.offset.z()) / 0.1, 0.0, 10.0)));
    s[k].points.push_back(i);
  }
  const auto m = measure_node_radii(s, cloud);
  for (NodeId v = 1; v < 10; ++v) {
    EXPECT_NEAR(m[v].radius, 0.1, 0.003) << v;
    EXPECT_GT(m[v].weight, 0.0) << v;
  }
  for (NodeId v = 0; v < s.node_count(); ++v) {  // one node alone measures the same
    EXPECT_EQ(measure_node_radius(s, cloud, v).radius, m[v].radius) << v;
    EXPECT_EQ(measure_node_radius(s, cloud, v).weight, m[v].weight) << v;
  }
}

// The skeleton of a sparse scan zigzags between the pieces its bands fell into: a straight
// vertical branch of radius 0.1 with its nodes 0.03 either side of the axis in turn every other
// node. Across the axis along a node's neighbours (tilted 50 degrees at every other node) the points
// lie on an ellipse; across the axis over a few radii they lie on the circle.
TEST(MeasureNodeRadii, AZigzagSkeletonMeasuresTheBranchAcrossItsAxis) {
  eval::SurfaceSampling sampling;
  sampling.points = 6000;
  const PointCloud cloud = eval::sample_cylinders({{Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 2), 0.1, 0.1}}, sampling);
  Skeleton s;
  const double step = 0.025, pi = std::acos(-1.0);
  const int nodes = 81;
  for (int i = 0; i < nodes; ++i) {
    SkeletonNode node;
    node.position = Eigen::Vector3d(0.03 * std::sin(0.5 * pi * i), 0.0, step * i);
    const NodeId v = add_node(s, node);
    if (i > 0) boost::add_edge(v - 1, v, s.graph);
  }
  for (std::uint32_t i = 0; i < cloud.size(); ++i) {
    const double z = cloud.positions[i].z() + cloud.offset.z();
    s[static_cast<NodeId>(std::lround(std::clamp(z / step, 0.0, nodes - 1.0)))].points.push_back(i);
  }
  const auto m = measure_node_radii(s, cloud);
  for (NodeId v = 8; v + 8 < s.node_count(); ++v) {  // the ends' reach is cut short
    EXPECT_NEAR(m[v].radius, 0.1, 0.003) << v;
    EXPECT_GT(m[v].weight, 0.0) << v;
  }
}

// A point repeated at the very same place counts once: every point written ten times measures
// as the points once; a node with five places repeated ten times has five points, too few to fit.
TEST(MeasureNodeRadii, RepeatedPointsCountOnce) {
  PointCloud cloud;
  Skeleton s;
  for (int i = 0; i < 3; ++i) {
    SkeletonNode node;
    node.position = Eigen::Vector3d(0.0, 0.0, 0.1 * i);
    const NodeId v = add_node(s, node);
    if (i > 0) boost::add_edge(v - 1, v, s.graph);
  }
  for (int k = 0; k < 12; ++k) {
    const double a = 0.5 * k;
    cloud.positions.emplace_back(0.2 * std::cos(a), 0.2 * std::sin(a), 0.1 + 0.001 * k);
  }
  for (std::uint32_t i = 0; i < 12; ++i) s[1].points.push_back(i);
  const RadiusMeasurement once = measure_node_radius(s, cloud, 1);
  EXPECT_NEAR(once.radius, 0.2, 1e-3);
  Skeleton repeated = s;
  PointCloud ten = cloud;
  for (int copy = 1; copy < 10; ++copy)
    for (std::uint32_t i = 0; i < 12; ++i) {
      repeated[1].points.push_back(static_cast<std::uint32_t>(ten.size()));
      ten.positions.push_back(cloud.positions[i]);
    }
  const RadiusMeasurement tenfold = measure_node_radius(repeated, ten, 1);
  EXPECT_EQ(tenfold.radius, once.radius);
  EXPECT_EQ(tenfold.weight, once.weight);
  // Five places, each ten times: fifty indices, five points (the default needs eight).
  Skeleton few = s;
  few[1].points.clear();
  for (int copy = 0; copy < 10; ++copy)
    for (std::uint32_t i = 0; i < 5; ++i) few[1].points.push_back(i + 12u * static_cast<std::uint32_t>(copy));
  EXPECT_EQ(measure_node_radius(few, ten, 1).radius, 0.0);
}

TEST(FitRadii, LeonardoAtEveryForkAndNoGrowthTowardTheTips) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> jitter(0.7, 1.3);
  for (int index = 1; index <= 6; ++index) {
    Skeleton s = eval::make_paper_tree(index, 1).skeleton;
    for (NodeId v = 0; v < s.node_count(); ++v) s[v].radius *= jitter(rng);  // measurements disagree
    RadiusStats stats;
    fit_radii(s, nullptr, {}, &stats);
    EXPECT_TRUE(stats.used_stored);
    SCOPED_TRACE("tree " + std::to_string(index));
    expect_pipe_model(s, 2.0);
  }
}

TEST(FitRadii, ExponentIsAnOption) {
  Skeleton s = eval::make_paper_tree(2, 1).skeleton;
  RadiusOptions o;
  o.exponent = 2.5;
  fit_radii(s, nullptr, o);
  expect_pipe_model(s, 2.5);
}

TEST(FitRadii, KeepsRadiiThatAlreadyObeyTheRule) {
  // A Y whose radii obey Leonardo exactly: the fit keeps the trunk and the arms.
  Skeleton s = test::y_shape(0.05, 0.6, 20);
  fit_radii(s, nullptr);
  EXPECT_NEAR(s[s.root].radius, 0.05, 0.05 * 0.05);
  EXPECT_NEAR(s[static_cast<NodeId>(s.node_count() - 1)].radius, 0.05 / std::sqrt(2.0), 0.05 * 0.1);
}

TEST(FitRadii, RefusesBadInput) {
  Skeleton empty;
  EXPECT_THROW(fit_radii(empty, nullptr), InputError);
  Skeleton zero = test::straight(1.0, 0.0, 4);
  EXPECT_THROW(fit_radii(zero, nullptr), InputError);
  Skeleton s = test::straight(1.0, 0.1, 4);
  RadiusOptions o;
  o.exponent = 0.5;
  EXPECT_THROW(fit_radii(s, nullptr, o), OptionError);
  RadiusOptions bent;
  bent.stiffness = -1.0;
  EXPECT_THROW(fit_radii(s, nullptr, bent), OptionError);
}

// With `complete`, a twig whose points the skeleton passed by becomes a branch, and the radii are
// fitted again with it: the pipe model holds at the new fork. The grafted twig carries its own length
// only (no tip allowance, its circle fits unused), so the trunk above the fork keeps nearly all of its
// cross section (with a tip's allowance the twig took half of it). Without the cell size it is refused.
TEST(FitRadii, CompletingGrowsATwigAndFitsItsRadii) {
  Skeleton s = test::straight(2.0, 0.05, 20);
  PointCloud cloud;
  for (int ring = 0; ring <= 100; ++ring)
    for (int k = 0; k < 24; ++k) {
      const double a = 2.0 * 3.14159265358979323846 * k / 24.0;
      cloud.positions.emplace_back(0.05 * std::cos(a), 0.05 * std::sin(a), 0.02 * ring);
    }
  for (int i = 0; i <= 40; ++i) {  // a twig from the trunk at z = 1 out to x = 0.6, two points a step
    const Eigen::Vector3d at = Eigen::Vector3d(0.05, 0, 1.0) + Eigen::Vector3d(0.55, 0, 0.3) * (i / 40.0);
    cloud.positions.push_back(at + Eigen::Vector3d(0, 0.01, 0));
    cloud.positions.push_back(at - Eigen::Vector3d(0, 0.01, 0));
  }
  for (std::uint32_t p = 0; p < cloud.size(); ++p) {  // every point to the node nearest to it
    NodeId best = 0;
    for (NodeId v = 1; v < s.node_count(); ++v)
      if ((s[v].position - cloud.positions[p]).norm() < (s[best].position - cloud.positions[p]).norm()) best = v;
    s[best].points.push_back(p);
  }
  RadiusOptions o;
  Skeleton plain = s;
  fit_radii(plain, &cloud, o);
  o.complete = true;
  Skeleton unscaled = s;
  EXPECT_THROW(fit_radii(unscaled, &cloud, o), OptionError);
  o.cell_size = 0.03;
  RadiusStats stats;
  fit_radii(s, &cloud, o, &stats);
  EXPECT_EQ(stats.completion.branches, 1u);
  EXPECT_EQ(s.node_count(), 21 + stats.completion.nodes);
  EXPECT_EQ(validate(s, cloud.size()), "");
  expect_pipe_model(s, 2.0);
  // The trunk keeps its measured radius, below the new fork and above it.
  EXPECT_NEAR(s[s.root].radius, 0.05, 0.01);
  EXPECT_GT(s[15].radius, 0.9 * plain[15].radius);  // z = 1.5
}

// A trunk 4 m tall (nodes every 0.1 m) with short stubs of 0.2 m (two nodes each) leaving node 10
// in `stubs` directions and sixteen twigs `twig` long (three nodes each) near the top. Twelve points on
// a circle across each node's branch: the trunk's and the stubs' of radius 0.1 (a stub's fits as
// wide as the trunk, as around a conifer's whorl the needles make them), the twigs' of 0.01.
struct StubTree {
  Skeleton skeleton;
  PointCloud cloud;
  std::vector<NodeId> stubs;  // each stub's first node
};

StubTree stub_tree(const std::vector<Eigen::Vector3d>& stubs, double twig = 0.3) {
  StubTree t;
  Skeleton& s = t.skeleton;
  s = test::straight(4.0, 0.1, 40);
  for (const Eigen::Vector3d& d : stubs) t.stubs.push_back(test::add_run(s, 10, s[10].position + 0.2 * d, 0.1, 2) - 1);
  const NodeId first_twig = s.node_count();
  std::vector<Eigen::Vector3d> twig_direction;
  for (int k = 0; k < 16; ++k) {
    const NodeId from = static_cast<NodeId>(24 + k);
    twig_direction.emplace_back(std::cos(0.8 * k), std::sin(0.8 * k), 0.0);
    test::add_run(s, from, s[from].position + twig * twig_direction.back(), 0.01, 3);
  }
  const auto ring = [&](NodeId v, const Eigen::Vector3d& along, double r) { test::add_ring(s, t.cloud, v, along, r); };
  for (NodeId v = 0; v <= 40; ++v) ring(v, Eigen::Vector3d::UnitZ(), 0.1);
  for (std::size_t k = 0; k < stubs.size(); ++k)
    for (NodeId v : {t.stubs[k], t.stubs[k] + 1}) ring(v, stubs[k], 0.1);
  for (NodeId v = first_twig; v < s.node_count(); ++v) ring(v, twig_direction[(v - first_twig) / 3], 0.01);
  return t;
}

// A short side branch whose circle fits are as wide as the trunk (stub_tree). By the fits alone the
// fork would give the stub a third of the trunk's cross section, and the trunk above it would
// narrow to 0.8 of what its own points say. Bounded by four times its pipe-model share, the stub
// gets less and the trunk keeps more of its width; without a cloud nothing is bounded.
TEST(FitRadii, AStubThatMeasuresItsParentDoesNotStarveIt) {
  StubTree t = stub_tree({Eigen::Vector3d::UnitX()});
  Skeleton& s = t.skeleton;
  const PointCloud& cloud = t.cloud;
  const NodeId fork = 10, stub = t.stubs.front() + 1;
  ASSERT_EQ(validate(s, cloud.size()), "");
  const NodeId above = 11;  // the trunk's first node above the fork
  Skeleton unbounded = s;
  RadiusOptions off;
  off.max_share_over_pipe = 0.0;
  off.stub_length = 0.0;  // the stub, 2 trunk radii long, is a twig here (see the stub tests below)
  fit_radii(unbounded, &cloud, off);
  RadiusOptions bound;
  ASSERT_EQ(bound.max_share_over_pipe, 4.0);  // the default
  bound.stub_length = 0.0;
  fit_radii(s, &cloud, bound);
  expect_pipe_model(s, 2.0);
  expect_pipe_model(unbounded, 2.0);
  // The fork measures 0.099 either way. Unbounded, the stub takes 34% of its cross section and
  // the trunk above it is 0.081. Bounded, the stub takes exactly four times its pipe share: what it
  // carries (0.1 m and a tip of 6 median twigs, 1.8 m) over what the fork's children carry (that and
  // the trunk's 2.9 m, sixteen twigs of 0.3 m and seventeen tips), 18.9%; the trunk above is 0.0895.
  EXPECT_NEAR(s[fork].radius, 0.099, 0.002);
  EXPECT_LT(unbounded[above].radius, 0.082);
  EXPECT_GT(unbounded[stub - 1].radius, 0.055);
  const double pipe_share = 1.9 / (1.9 + 2.9 + 16 * 2.1 + 1.8);
  EXPECT_NEAR(std::pow(s[stub - 1].radius / s[fork].radius, 2.0), 4.0 * pipe_share, 1e-3);
  EXPECT_GT(s[above].radius, 0.089);
  // Stored radii are bounded as fits are: a skeleton saved by `skeletonize` carries the level
  // sets' radii, which take in a conifer's needles as circle fits do (TreeLS's pine, modelled from
  // its saved skeleton, had a DBH of 0.04 m unbounded, 0.19 m bounded; 0.26 m from its points). The
  // stub stored as thick as the fork takes four times its pipe share, not half the fork.
  Skeleton stored = s;
  for (NodeId v = 0; v < stored.node_count(); ++v) stored[v].radius = v == stub - 1 || v == stub ? 0.1 : s[v].radius;
  stored[fork].radius = 0.1;
  Skeleton stored_unbounded = stored;
  fit_radii(stored, nullptr, bound);
  fit_radii(stored_unbounded, nullptr, off);
  expect_pipe_model(stored, 2.0);
  EXPECT_NEAR(std::pow(stored[stub - 1].radius / stored[fork].radius, 2.0), 4.0 * pipe_share, 1e-3);
  EXPECT_GT(std::pow(stored_unbounded[stub - 1].radius / stored_unbounded[fork].radius, 2.0), 0.3);
  EXPECT_GT(stored[above].radius, stored_unbounded[above].radius * 1.1);
  RadiusOptions bad;
  bad.max_share_over_pipe = 0.5;
  EXPECT_THROW(fit_radii(s, &cloud, bad), OptionError);
  bad.max_share_over_pipe = std::numeric_limits<double>::infinity();  // not "off": 0 is
  EXPECT_THROW(fit_radii(s, &cloud, bad), OptionError);
}

// Two such stubs at one fork: each takes its bound, no more. (Bounded against the sum of what the
// children's fits say, each stub's own wide fit raised its bound: the two took 21.2% each, 18.1% here.)
TEST(FitRadii, StubsSharingAForkTakeNoMoreThanTheirBoundTogether) {
  StubTree t = stub_tree({Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY()});
  Skeleton& s = t.skeleton;
  RadiusOptions twigs;
  twigs.stub_length = 0.0;
  fit_radii(s, &t.cloud, twigs);
  expect_pipe_model(s, 2.0);
  const NodeId fork = 10, above = 11;
  const double pipe_share = 1.9 / (2 * 1.9 + 2.9 + 16 * 2.1 + 1.8);  // as in the test above
  for (NodeId stub : t.stubs) EXPECT_NEAR(std::pow(s[stub].radius / s[fork].radius, 2.0), 4.0 * pipe_share, 1e-3);
  EXPECT_NEAR(std::pow(s[above].radius / s[fork].radius, 2.0), 1.0 - 8.0 * pipe_share, 1e-3);
}

// At K = 1 every child of a fork may take its pipe share at most, so wherever the fits ask more
// than that of one child, each gets exactly its pipe share; at a root that forks (its cross section
// the children's estimates) the root keeps what the fits say. A V from the root: two arms of 1 m
// and 0.5 m, rings of 0.05 on both.
TEST(FitRadii, AtABoundOfOneEachChildGetsItsPipeShare) {
  Skeleton s = test::lone_root(0.05);
  const NodeId long_end = test::add_run(s, s.root, Eigen::Vector3d(0.6, 0.0, 0.8), 0.05, 10);
  const NodeId short_end = test::add_run(s, s.root, Eigen::Vector3d(-0.3, 0.0, 0.4), 0.05, 5);
  PointCloud cloud;
  for (NodeId v = 1; v < s.node_count(); ++v)
    test::add_ring(s, cloud, v, v <= long_end ? Eigen::Vector3d(0.6, 0.0, 0.8) : Eigen::Vector3d(-0.6, 0.0, 0.8), 0.05);
  ASSERT_EQ(validate(s, cloud.size()), "");
  RadiusOptions o;
  o.max_share_over_pipe = 1.0;
  o.stub_length = 0.0;
  fit_radii(s, &cloud, o);
  expect_pipe_model(s, 2.0);
  // Each arm's first node carries what lies beyond it (0.9 and 0.4 m) and a tip of 6 median twig
  // lengths (the median of 1 and 0.5: 1). The fits ask half each, over the short arm's pipe share.
  const double long_share = 6.9 / (6.9 + 6.4);
  EXPECT_NEAR(std::pow(s[1].radius / s[s.root].radius, 2.0), long_share, 1e-4);
  EXPECT_NEAR(std::pow(s[short_end - 4].radius / s[s.root].radius, 2.0), 1.0 - long_share, 1e-4);
  EXPECT_NEAR(s[s.root].radius, 0.05 * std::sqrt(2.0), 0.002);  // the two arms' fits, summed
}

// Stubs do not cut the trunk's taper in two. The trunk of stub_tree measures 0.1 but for three nodes
// just above the stubs' fork, whose rings are half as wide. Fitted as a branch of its own from the
// fork, with its start and taper from its own fits, the trunk above came out 4-6% wider than the
// trunk of the same tree without the stubs; fitted whole, with the stubs hung back after, it is that
// trunk to 1%.
TEST(FitRadii, StubsDoNotRestartTheTaperOfTheBranchTheyLeave) {
  const auto narrowed = [](StubTree t) {
    for (NodeId v : {11, 12, 13})
      for (auto p : t.skeleton[v].points)
        t.cloud.positions[p] = t.skeleton[v].position + 0.5 * (t.cloud.positions[p] - t.skeleton[v].position);
    return t;
  };
  StubTree with = narrowed(stub_tree({Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY()}, 0.9));
  StubTree without = narrowed(stub_tree({}, 0.9));
  RadiusStats stats;
  fit_radii(with.skeleton, &with.cloud, {}, &stats);
  ASSERT_EQ(stats.stubs, 3u);
  fit_radii(without.skeleton, &without.cloud, {});
  expect_pipe_model(with.skeleton, 2.0);
  for (NodeId v = 11; v <= 23; ++v) {
    SCOPED_TRACE(v);
    EXPECT_NEAR(with.skeleton[v].radius / without.skeleton[v].radius, 1.0, 0.01);
  }
}

// A trunk from the origin up to `height` (`trunk_steps` edges) that forks into two arms 1 m long,
// toward +x and -x and 0.8 m up (`arm_steps` edges each): the left arm's nodes first, then the right's.
struct TwoArms {
  Skeleton s;
  NodeId fork, left_end, right_end;
};

TwoArms two_arms(double trunk_radius, double height, int trunk_steps, double arm_radius, int arm_steps) {
  TwoArms t{test::lone_root(trunk_radius), 0, 0, 0};
  t.fork = test::add_run(t.s, t.s.root, Eigen::Vector3d(0, 0, height), trunk_radius, trunk_steps);
  t.left_end = test::add_run(t.s, t.fork, Eigen::Vector3d(0.6, 0, height + 0.8), arm_radius, arm_steps);
  t.right_end = test::add_run(t.s, t.fork, Eigen::Vector3d(-0.6, 0, height + 0.8), arm_radius, arm_steps);
  return t;
}

// A trunk 1 m tall with rings of 0.05 forks into two arms of 1 m: the points measure one, whose
// rings (0.15) are three times the trunk's, and not the other. The unmeasured arm's estimate comes
// from the global scale the trunk sets, nine times under its sibling's fit: alone it got a twentieth
// of the fork; with the floor it gets a quarter of its pipe share (half the fork), an eighth.
TEST(FitRadii, AChildTheFitsDoNotMeasureGetsAtLeastAQuarterOfItsPipeShare) {
  TwoArms y = two_arms(0.05, 1.0, 10, 0.05, 10);
  Skeleton& s = y.s;
  const NodeId fork = y.fork, measured_end = y.left_end, bare_end = y.right_end;
  PointCloud cloud;
  for (NodeId v = 0; v < fork; ++v) test::add_ring(s, cloud, v, Eigen::Vector3d::UnitZ(), 0.05);
  for (NodeId v = fork + 1; v <= measured_end; ++v) test::add_ring(s, cloud, v, Eigen::Vector3d(0.6, 0, 0.8), 0.15);
  ASSERT_EQ(validate(s, cloud.size()), "");
  const NodeId measured_first = fork + 1, bare_first = measured_end + 1;
  ASSERT_EQ(bare_end, bare_first + 9);
  const auto share = [&](const Skeleton& fitted, NodeId child) { return std::pow(fitted[child].radius / fitted[fork].radius, 2.0); };

  RadiusOptions o;
  ASSERT_EQ(o.min_share_of_pipe, 0.25);  // the default
  Skeleton floored = s;
  fit_radii(floored, &cloud, o);
  expect_pipe_model(floored, 2.0);
  EXPECT_NEAR(share(floored, bare_first), 0.125, 1e-6);
  EXPECT_NEAR(share(floored, measured_first), 0.875, 1e-6);
  // The bare arm is no thinner at its tip than 0.05 times its start's cross section (the taper's
  // own floor): its radius stays within a factor of five of where it starts.
  EXPECT_GT(floored[bare_end].radius, 0.2 * floored[bare_first].radius);

  o.min_share_of_pipe = 0.0;
  Skeleton unfloored = s;
  fit_radii(unfloored, &cloud, o);
  EXPECT_LT(share(unfloored, bare_first), 0.07);
  o.min_share_of_pipe = 1.0;  // the pipe model's shares wherever the fits give less
  Skeleton pipe = s;
  fit_radii(pipe, &cloud, o);
  EXPECT_NEAR(share(pipe, bare_first), 0.5, 1e-6);
  for (double bad : {-0.1, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
    o.min_share_of_pipe = bad;
    EXPECT_THROW(fit_radii(pipe, &cloud, o), OptionError);
  }
}

// A trunk 2 m tall (nodes every 5 cm, rings of 0.1) forks at its top into two arms 1 m long whose
// rings (0.0707) obey Leonardo's rule. The ring of the node 5 cm below the fork is 0.07, as a node
// whose band the fork split keeps part of its points and fits a small circle. Taken into the
// trunk's taper it pulled the trunk's end down (radii never grow toward the tips), and the arms
// started under their own fits, which cannot raise them; within one of its radii of the fork
// (RadiusOptions::fork_margin) it is left out, and the fork and the arms keep what their points say.
TEST(FitRadii, AFitSplitByTheForkAheadDoesNotThinTheBranchAndAllItCarries) {
  TwoArms y = two_arms(0.1, 2.0, 40, 0.0707, 20);
  Skeleton& s = y.s;
  const NodeId fork = y.fork, left_end = y.left_end, right_end = y.right_end;
  PointCloud cloud;
  for (NodeId v = 0; v < fork; ++v) test::add_ring(s, cloud, v, Eigen::Vector3d::UnitZ(), v + 1 == fork ? 0.07 : 0.1);
  for (NodeId v = fork + 1; v <= left_end; ++v) test::add_ring(s, cloud, v, Eigen::Vector3d(0.6, 0, 0.8), 0.0707);
  for (NodeId v = left_end + 1; v <= right_end; ++v) test::add_ring(s, cloud, v, Eigen::Vector3d(-0.6, 0, 0.8), 0.0707);
  ASSERT_EQ(validate(s, cloud.size()), "");
  const NodeId arm = fork + 1;

  RadiusOptions o;
  ASSERT_EQ(o.fork_margin, 1.0);  // the default
  Skeleton kept = s;
  fit_radii(kept, &cloud, o);
  expect_pipe_model(kept, 2.0);
  EXPECT_NEAR(kept[fork].radius, 0.1, 0.002);
  EXPECT_NEAR(kept[arm].radius, 0.0707, 0.0015);
  EXPECT_NEAR(kept[left_end].radius, 0.0707, 0.0015);

  o.fork_margin = 0.0;  // every fit counts
  Skeleton pulled = s;
  fit_radii(pulled, &cloud, o);
  expect_pipe_model(pulled, 2.0);
  EXPECT_LT(pulled[fork].radius, 0.095);
  EXPECT_LT(pulled[arm].radius, 0.067);
  EXPECT_LT(pulled[left_end].radius, 0.067);
  for (double bad : {-1.0, std::numeric_limits<double>::infinity()}) {
    o.fork_margin = bad;
    EXPECT_THROW(fit_radii(pulled, &cloud, o), OptionError);
  }
}

// The same stubs, 2 trunk radii long, under the default 6.5 (the twigs 0.9 m long, 9 trunk radii;
// the trunk's last 0.1 m above the top twig is a stub too): they carry their own length only, their
// fits unused, and the trunk above the fork keeps almost all of its cross section. With stubs off
// they are twigs, and the trunk above them narrows. The report says how many stubs.
TEST(FitRadii, TipsShorterThanTheStubLengthAreStubs) {
  StubTree t = stub_tree({Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY()}, 0.9);
  Skeleton s = t.skeleton;
  RadiusOptions o;
  ASSERT_EQ(o.stub_length, 6.5);  // the default
  RadiusStats stats;
  fit_radii(s, &t.cloud, o, &stats);
  expect_pipe_model(s, 2.0);
  EXPECT_EQ(stats.stubs, 3u);
  const NodeId fork = 10, above = 11;
  for (NodeId stub : t.stubs) {
    EXPECT_LT(std::pow(s[stub].radius / s[fork].radius, 2.0), 0.005);
    // A stub is a cylinder: its tip as thick as its start (tapered to what lies above each node,
    // its tip came out at a ten-millionth of a metre).
    EXPECT_NEAR(s[stub + 1].radius, s[stub].radius, 1e-12);
  }
  EXPECT_GT(std::pow(s[above].radius / s[fork].radius, 2.0), 0.99);
  EXPECT_NEAR(s[above].radius, 0.1, 0.002);  // what the trunk's points say
  Skeleton twigs = t.skeleton;
  o.stub_length = 0.0;
  fit_radii(twigs, &t.cloud, o, &stats);
  EXPECT_EQ(stats.stubs, 0u);
  for (NodeId stub : t.stubs) EXPECT_GT(std::pow(twigs[stub].radius / twigs[fork].radius, 2.0), 0.15);  // bounded
  EXPECT_LT(twigs[above].radius, 0.085);
  // Stored radii are taken as they are: no stubs without a cloud.
  Skeleton stored = s;
  fit_radii(stored, nullptr, RadiusOptions{}, &stats);
  EXPECT_EQ(stats.stubs, 0u);
  o.stub_length = -1.0;
  EXPECT_THROW(fit_radii(s, &t.cloud, o), OptionError);
  o.stub_length = std::numeric_limits<double>::infinity();
  EXPECT_THROW(fit_radii(s, &t.cloud, o), OptionError);
}

}  // namespace
}  // namespace treeskel::modeling
