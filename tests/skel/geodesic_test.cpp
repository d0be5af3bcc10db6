#include "treeskel/geodesic.h"

#include <gtest/gtest.h>

#include <limits>
#include <random>

namespace treeskel {
namespace {

/// An L-shaped row of cells: up the z axis, then along x.
struct LShape {
  PointCloud cloud;
  OctreeCells cells;
  CellGraph graph;
  LShape() {
    for (int z = 0; z < 10; ++z) cloud.positions.emplace_back(0.5, 0.5, z + 0.5);
    for (int x = 1; x < 10; ++x) cloud.positions.emplace_back(x + 0.5, 0.5, 9.5);
    cloud.positions.emplace_back(16.0, 0.0, 0.0);  // two pins fix the bounding cube to [0, 16]³
    cloud.positions.emplace_back(0.0, 16.0, 16.0);
    OctreeOptions o;
    o.depth = 4;
    cells = build_octree_cells(cloud, o);
    NeighbourGraphOptions g;
    g.bridge_distance = -1.0;
    graph = build_neighbour_graph(cells, g);
  }
};

TEST(Geodesic, DistanceFollowsTheGraphNotTheStraightLine) {
  const LShape l;
  const auto main = select_main_part(l.cells, l.graph);
  const auto roots = select_root_cells(l.cells, l.graph, main.in_tree, {});
  ASSERT_EQ(roots.size(), 3u);  // the slice is two cells thick: z = 0.5, 1.5 and 2.5 are within it
  const auto geo = geodesic_distance(l.graph, roots);
  const auto tip = l.cells.find({9, 0, 9});
  // From the slice top (z 2.5) up to z 8.5 is 6, a diagonal step cuts the corner (sqrt 2), then 8
  // along x: the straight line would be about 11.4.
  EXPECT_NEAR(geo.distance[tip], 14.0 + std::sqrt(2.0), 1e-9);
  const auto pin = l.cells.find({15, 0, 0});
  EXPECT_TRUE(std::isinf(geo.distance[pin]));
  EXPECT_EQ(geo.predecessor[pin], -1);
  // Predecessors lead back to a root.
  std::int64_t c = tip;
  int steps = 0;
  while (geo.predecessor[c] >= 0 && steps < 100) {
    c = geo.predecessor[c];
    ++steps;
  }
  EXPECT_TRUE(std::find(roots.begin(), roots.end(), static_cast<std::uint32_t>(c)) != roots.end());
}

TEST(Geodesic, TiesGoToTheLowestIndexLikeThePlainSearch) {
  // Random graphs with small integer weights (many paths of equal length): distances and
  // predecessors equal those of the plain O(n^2) search that takes the nearest, then lowest, cell.
  std::mt19937 rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    const std::uint32_t n = 50 + 30 * static_cast<std::uint32_t>(trial);
    std::vector<std::vector<std::pair<std::uint32_t, double>>> adj(n);
    std::uniform_int_distribution<std::uint32_t> cell(0, n - 1);
    std::uniform_int_distribution<int> weight(0, 3);
    for (std::uint32_t e = 0; e < 3 * n; ++e) {
      const auto a = cell(rng), b = cell(rng);
      if (a == b) continue;
      const double w = weight(rng);
      adj[a].emplace_back(b, w);
      adj[b].emplace_back(a, w);
    }
    CellGraph graph;
    graph.offsets.push_back(0);
    for (const auto& row : adj) {
      for (const auto& [o, w] : row) {
        graph.targets.push_back(o);
        graph.weights.push_back(w);
      }
      graph.offsets.push_back(static_cast<std::uint32_t>(graph.targets.size()));
    }
    const std::vector<std::uint32_t> sources{cell(rng), cell(rng)};
    const GeodesicField field = geodesic_distance(graph, sources);

    const double inf = std::numeric_limits<double>::infinity();
    std::vector<double> distance(n, inf);
    std::vector<std::int64_t> predecessor(n, -1);
    std::vector<bool> done(n, false);
    for (auto s : sources) distance[s] = 0.0;
    for (;;) {
      std::int64_t c = -1;
      for (std::uint32_t v = 0; v < n; ++v)
        if (!done[v] && distance[v] < inf && (c < 0 || distance[v] < distance[c])) c = v;
      if (c < 0) break;
      done[c] = true;
      for (const auto& [o, w] : adj[c])
        if (distance[c] + w < distance[o]) {
          distance[o] = distance[c] + w;
          predecessor[o] = c;
        }
    }
    for (std::uint32_t v = 0; v < n; ++v) {
      EXPECT_EQ(field.distance[v], distance[v]) << "trial " << trial << ", cell " << v;
      EXPECT_EQ(static_cast<std::int64_t>(field.predecessor[v]), predecessor[v]) << "trial " << trial << ", cell " << v;
    }
  }
}

TEST(Geodesic, RootPointAndUpAxisChooseTheStart) {
  const LShape l;
  const auto main = select_main_part(l.cells, l.graph);
  RootOptions at_tip;
  at_tip.point = Eigen::Vector3d(9.5, 0.5, 9.5);
  const auto roots = select_root_cells(l.cells, l.graph, main.in_tree, at_tip);
  ASSERT_EQ(roots.size(), 1u);
  EXPECT_EQ(roots[0], l.cells.find({9, 0, 9}));

  RootOptions sideways;
  sideways.up = -Eigen::Vector3d::UnitX();  // "lowest" is now the largest x
  const auto side_roots = select_root_cells(l.cells, l.graph, main.in_tree, sideways);
  ASSERT_EQ(side_roots.size(), 3u);  // x = 9.5, 8.5 and 7.5
  EXPECT_EQ(side_roots.front(), std::min({l.cells.find({7, 0, 9}), l.cells.find({8, 0, 9}), l.cells.find({9, 0, 9})}));
}

}  // namespace
}  // namespace treeskel
