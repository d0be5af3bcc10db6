#include "treeskel/refine.h"

#include "support/synthetic.h"

#include <gtest/gtest.h>

#include <numeric>

namespace treeskel {
namespace {

using test::tube;

/// A fork node placed too high: it holds the points of two separate branch pieces whose centres are
/// far from it; each child branch hangs below one of the pieces.
TEST(Refine, SplitsAForkWhoseClustersLieFarApart) {
  eval::SurfaceSampling o;
  o.points = 400;
  PointCloud cloud = eval::sample_cylinders({tube({-0.5, 0, 1.0}, {-0.5, 0, 1.1}, 0.05)}, o);
  o.seed = 2;
  const PointCloud right = eval::sample_cylinders({tube({0.5, 0, 1.0}, {0.5, 0, 1.1}, 0.05)}, o);
  cloud.positions.insert(cloud.positions.end(), right.positions.begin(), right.positions.end());

  Skeleton s;
  auto add = [&](Eigen::Vector3d p, double r, std::vector<std::uint32_t> pts) {
    SkeletonNode n;
    n.position = p;
    n.radius = r;
    n.points = std::move(pts);
    return add_node(s, n);
  };
  const NodeId base = add({0, 0, 0}, 0.07, {});
  std::vector<std::uint32_t> all(cloud.size());
  std::iota(all.begin(), all.end(), 0u);
  const NodeId fork = add({0, 0, 1.05}, 0.5, all);
  const NodeId left_child = add({-0.5, 0, 1.3}, 0.05, {});
  const NodeId right_child = add({0.5, 0, 1.3}, 0.05, {});
  boost::add_edge(base, fork, s.graph);
  boost::add_edge(fork, left_child, s.graph);
  boost::add_edge(fork, right_child, s.graph);
  s.root = base;

  const std::size_t added = refine_topology(s, cloud, {});
  EXPECT_EQ(added, 2u);
  EXPECT_EQ(validate(s, cloud.size()), "");
  EXPECT_EQ(count_branch_points(s.graph), 0u);  // the empty fork is gone: the base forks, with 2 children
  EXPECT_EQ(boost::degree(s.root, s.graph), 2u);
  // Each new node sits at the centre of its piece.
  for (auto w : boost::make_iterator_range(boost::adjacent_vertices(s.root, s.graph))) {
    const double x = s[w].position.x() < 0 ? -0.5 : 0.5;
    EXPECT_LT((s[w].position - Eigen::Vector3d(x, 0, 1.05)).norm(), 0.01);
    EXPECT_NEAR(s[w].radius, 0.05, 0.01);
  }
}

TEST(Refine, KeepsAForkWhoseClustersAreClose) {
  // Two children of a thick node whose points form one ring around it: no cluster centre is farther
  // than the Leonardo threshold.
  eval::SurfaceSampling o;
  o.points = 800;
  const PointCloud cloud = eval::sample_cylinders({tube({0, 0, 1.0}, {0, 0, 1.1}, 0.1)}, o);
  Skeleton s;
  SkeletonNode base, fork, a, b;
  fork.position = {0, 0, 1.05};
  fork.points.resize(cloud.size());
  std::iota(fork.points.begin(), fork.points.end(), 0u);
  a.position = {-0.1, 0, 1.3};
  a.radius = 0.07;
  b.position = {0.1, 0, 1.3};
  b.radius = 0.07;
  add_node(s, base);
  add_node(s, fork);
  add_node(s, a);
  add_node(s, b);
  boost::add_edge(0, 1, s.graph);
  boost::add_edge(1, 2, s.graph);
  boost::add_edge(1, 3, s.graph);
  EXPECT_EQ(refine_topology(s, cloud, {}), 0u);
  EXPECT_EQ(count_branch_points(s.graph), 1u);
}

}  // namespace
}  // namespace treeskel
