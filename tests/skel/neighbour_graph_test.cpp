#include "treeskel/neighbour_graph.h"

#include <gtest/gtest.h>

namespace treeskel {
namespace {

/// One point at the centre of each listed grid cell of a unit grid (depth chosen so cells are 1 wide).
PointCloud grid_points(const std::vector<Eigen::Vector3i>& cells_at, int extent) {
  PointCloud c;
  for (const auto& g : cells_at) c.positions.push_back(g.cast<double>() + Eigen::Vector3d::Constant(0.5));
  // Corner points pin the bounding cube to [0, extent]: they land in cells far from the others.
  c.positions.emplace_back(0.0, 0.0, 0.0);
  c.positions.emplace_back(extent, extent, extent);
  return c;
}

/// Adds `n` points (at most 10) inside the unit grid cell `g`, none repeating another.
void put_points(PointCloud& cloud, const Eigen::Vector3i& g, int n) {
  for (int i = 0; i < n; ++i)
    cloud.positions.push_back(g.cast<double>() + Eigen::Vector3d(0.3 + 0.04 * i, 0.5, 0.7 - 0.04 * i));
}

/// The octree cells of `cloud` at `depth`.
OctreeCells cells_at_depth(const PointCloud& cloud, int depth) {
  OctreeOptions o;
  o.depth = depth;
  return build_octree_cells(cloud, o);
}

/// The octree cells of `cloud` with corner points pinning its cube to [0, 32]: cells 1 wide at depth 5.
OctreeCells pinned_unit_cells(PointCloud cloud) {
  cloud.positions.emplace_back(0.0, 0.0, 0.0);
  cloud.positions.emplace_back(32.0, 32.0, 32.0);
  return cells_at_depth(cloud, 5);
}

TEST(NeighbourGraph, OctreeAdjacencyIsTheTwentySixNeighbourhood) {
  std::vector<Eigen::Vector3i> block;
  for (int z = 4; z < 7; ++z)
    for (int y = 4; y < 7; ++y)
      for (int x = 4; x < 7; ++x) block.emplace_back(x, y, z);
  const PointCloud cloud = grid_points(block, 16);
  const OctreeCells cells = cells_at_depth(cloud, 4);  // 16 cells of size 1
  ASSERT_DOUBLE_EQ(cells.cell_size, 1.0);
  NeighbourGraphOptions g;
  g.bridge_distance = -1.0;
  const CellGraph graph = build_neighbour_graph(cells, g);
  const auto centre = cells.find({5, 5, 5});
  ASSERT_GE(centre, 0);
  EXPECT_EQ(graph.offsets[centre + 1] - graph.offsets[centre], 26u);
  const auto corner = cells.find({4, 4, 4});
  EXPECT_EQ(graph.offsets[corner + 1] - graph.offsets[corner], 7u);
  // Symmetric, and weights are the distances between medians.
  for (std::size_t c = 0; c < graph.vertex_count(); ++c)
    for (auto e = graph.offsets[c]; e < graph.offsets[c + 1]; ++e) {
      const auto o2 = graph.targets[e];
      bool back = false;
      for (auto f = graph.offsets[o2]; f < graph.offsets[o2 + 1]; ++f) back |= graph.targets[f] == c;
      EXPECT_TRUE(back);
      EXPECT_NEAR(graph.weights[e], (cells.medians[c] - cells.medians[o2]).norm(), 1e-12);
    }
  std::uint32_t parts = 0;
  connected_components(graph, &parts);
  EXPECT_EQ(parts, 3u);  // the block and the two corner pins
}

TEST(NeighbourGraph, BridgesGapsShorterThanTheBridgeDistance) {
  std::vector<Eigen::Vector3i> line;
  for (int z = 0; z < 6; ++z) line.emplace_back(8, 8, z + 1);
  for (int z = 9; z < 15; ++z) line.emplace_back(8, 8, z);  // a gap of two empty cells (z = 7, 8)
  PointCloud cloud;
  for (const auto& g : line) cloud.positions.push_back(g.cast<double>() + Eigen::Vector3d(0.5, 0.5, 0.5));
  cloud.positions.emplace_back(0.0, 0.0, 0.0);
  cloud.positions.emplace_back(16.0, 0.0, 0.0);
  const OctreeCells cells = cells_at_depth(cloud, 4);

  NeighbourGraphOptions none;
  none.bridge_distance = -1.0;
  std::uint32_t parts = 0;
  connected_components(build_neighbour_graph(cells, none), &parts);
  EXPECT_EQ(parts, 4u);

  NeighbourGraphOptions near;
  near.bridge_distance = 3.5;  // joins the line (gap 3) but not the pins, which are farther
  const CellGraph bridged = build_neighbour_graph(cells, near);
  connected_components(bridged, &parts);
  EXPECT_EQ(parts, 3u);
  EXPECT_EQ(bridged.bridges, 1u);

  const MainPart main = select_main_part(cells, bridged, near);
  EXPECT_EQ(main.parts, 3u);
  EXPECT_EQ(main.left_out.total(), 2u);
  EXPECT_EQ(std::count(main.in_tree.begin(), main.in_tree.end(), true), 12);
}

TEST(NeighbourGraph, BridgeLinksEachPartToItsNearestForeignCell) {
  // A line of cells along z, two small parts beside it several cells away (across blocks of the
  // search), and two corner pins out of reach. Each small part is linked by its shortest link.
  std::vector<Eigen::Vector3i> at;
  for (int z = 0; z < 31; ++z) at.emplace_back(8, 8, z);
  at.emplace_back(13, 8, 10);  // part A: 5 cells from (8, 8, 10)
  at.emplace_back(14, 8, 10);
  at.emplace_back(8, 11, 25);  // part B: 3 cells from (8, 8, 25)
  at.emplace_back(8, 12, 26);
  const PointCloud cloud = grid_points(at, 32);
  const OctreeCells cells = cells_at_depth(cloud, 5);
  ASSERT_DOUBLE_EQ(cells.cell_size, 1.0);
  NeighbourGraphOptions g;
  g.bridge_distance = 6.0;
  const CellGraph graph = build_neighbour_graph(cells, g);
  EXPECT_EQ(graph.bridges, 2u);
  const auto linked = [&](const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
    const auto i = cells.find(a), j = cells.find(b);
    for (auto e = graph.offsets[i]; e < graph.offsets[i + 1]; ++e)
      if (graph.targets[e] == j) return true;
    return false;
  };
  EXPECT_TRUE(linked({13, 8, 10}, {8, 8, 10}));
  EXPECT_TRUE(linked({8, 11, 25}, {8, 8, 25}));
  EXPECT_FALSE(linked({14, 8, 10}, {8, 8, 10}));
  std::uint32_t parts = 0;
  connected_components(graph, &parts);
  EXPECT_EQ(parts, 3u);  // the line with A and B, and the two pins

  // Out of reach: a bridge distance under 3 joins neither part (far bridging off: parts of two
  // points are far bridged by default).
  g.bridge_distance = 2.9;
  g.far_bridge_distance = -1.0;
  EXPECT_EQ(build_neighbour_graph(cells, g).bridges, 0u);
}

TEST(NeighbourGraph, FarBridgingJoinsATwigPieceOfTenPointsButNotFewerStrayPoints) {
  // A line of cells along z (3 points each), a twig piece of 10 points 4 cells beside it, and 9
  // stray points 4 cells beside it elsewhere: beyond the near bridge (2.5), within the far one (5).
  PointCloud cloud;
  for (int z = 0; z < 31; ++z) put_points(cloud, {8, 8, z}, 3);
  put_points(cloud, {12, 8, 15}, 5);  // the twig piece: two cells, 10 points
  put_points(cloud, {13, 8, 15}, 5);
  put_points(cloud, {8, 12, 25}, 9);  // the stray points
  const OctreeCells cells = pinned_unit_cells(cloud);
  ASSERT_DOUBLE_EQ(cells.cell_size, 1.0);
  NeighbourGraphOptions g;
  g.bridge_distance = 2.5;
  g.far_bridge_distance = 5.0;
  // The default floor (3 points) joins the stray points too: a part of 9 points is a twig piece to
  // it. The test of the floor takes 10.
  EXPECT_EQ(build_neighbour_graph(cells, g).bridges, 2u);
  g.far_bridge_min_points = 10;
  const CellGraph graph = build_neighbour_graph(cells, g);
  EXPECT_EQ(graph.bridges, 1u);
  const auto twig = cells.find({12, 8, 15}), trunk = cells.find({8, 8, 15});
  ASSERT_GE(twig, 0);
  ASSERT_GE(trunk, 0);
  const auto id = connected_components(graph);
  EXPECT_EQ(id[twig], id[trunk]);
  EXPECT_NE(id[cells.find({8, 12, 25})], id[trunk]);
  const MainPart main = select_main_part(cells, graph, g);
  EXPECT_EQ(main.parts, 4u);  // the line with the twig, the stray points, the two pins
  EXPECT_EQ(main.left_out.total(), 11u);

  // A floor above the twig's ten points, or a share of the cloud above them, leaves it out too.
  g.far_bridge_min_points = 11;
  EXPECT_EQ(build_neighbour_graph(cells, g).bridges, 0u);
  g.far_bridge_min_points = 10;
  g.far_bridge_fraction = 0.1;  // 11 of the 114 points
  EXPECT_EQ(build_neighbour_graph(cells, g).bridges, 0u);
  // With the near bridge alone long enough, both join whatever their size.
  g.bridge_distance = 4.5;
  EXPECT_EQ(build_neighbour_graph(cells, g).bridges, 2u);
}

TEST(NeighbourGraph, PiecesNearerEachOtherThanTheTreeAreJoinedToTheTreeToo) {
  // A line of cells along z (the tree), piece A 4 cells beside it and piece B 2 cells beyond A, 6
  // from the tree: within the far bridge (5) A reaches both, B only A. Every probe of A meets B
  // first, so the first round joins A and B; the second, A and B as one, joins them to the tree.
  PointCloud cloud;
  for (int z = 0; z < 31; ++z) put_points(cloud, {8, 8, z}, 3);
  for (int z = 15; z < 18; ++z) put_points(cloud, {12, 8, z}, 3);  // A
  for (int z = 15; z < 18; ++z) put_points(cloud, {14, 8, z}, 3);  // B
  const OctreeCells cells = pinned_unit_cells(cloud);
  ASSERT_DOUBLE_EQ(cells.cell_size, 1.0);
  NeighbourGraphOptions g;
  g.bridge_distance = 1.5;
  g.far_bridge_distance = 5.0;
  const CellGraph graph = build_neighbour_graph(cells, g);
  EXPECT_EQ(graph.bridges, 2u);
  const auto id = connected_components(graph);
  const auto trunk = id[cells.find({8, 8, 16})];
  EXPECT_EQ(id[cells.find({12, 8, 16})], trunk);
  EXPECT_EQ(id[cells.find({14, 8, 16})], trunk);
  const MainPart main = select_main_part(cells, graph, g);
  EXPECT_EQ(main.left_out.total(), 2u);  // the two pins

  // In one round, as before: A and B join each other, not the tree.
  g.bridge_rounds = 1;
  const CellGraph first_only = build_neighbour_graph(cells, g);
  EXPECT_EQ(first_only.bridges, 1u);
  const auto apart = connected_components(first_only);
  EXPECT_EQ(apart[cells.find({12, 8, 16})], apart[cells.find({14, 8, 16})]);
  EXPECT_NE(apart[cells.find({12, 8, 16})], apart[cells.find({8, 8, 16})]);
}

TEST(NeighbourGraph, SparseCellsOfAGrownCubeNeighbourCellsTwoApart) {
  // Lines of cells one empty cell apart along x, on a cube grown by 1.25 (cells 1.25 wide at depth
  // 4 over a cloud 16 wide): one point a cell (sparse: fewer than 2 on average) joins up; three
  // points a cell (dense) stays apart, and so does the sparse line without the option.
  const double cell = 1.25;
  const auto line = [&](int y, int per_cell) {
    PointCloud c;
    for (int x = 1; x < 12; x += 2)
      for (int i = 0; i < per_cell; ++i)
        c.positions.emplace_back((x + 0.3 + 0.2 * i) * cell, (y + 0.5) * cell, 5.5 * cell);
    c.positions.emplace_back(0.0, 0.0, 0.0);  // pins: the points' cube is [0, 16]
    c.positions.emplace_back(16.0, 16.0, 16.0);
    return c;
  };
  OctreeOptions grown;
  grown.depth = 4;
  grown.cube_scale = 1.25;
  NeighbourGraphOptions g;
  g.bridge_distance = -1.0;
  const auto parts_of = [&](const PointCloud& cloud, const NeighbourGraphOptions& options, const OctreeOptions& octree) {
    const OctreeCells cells = build_octree_cells(cloud, octree);
    EXPECT_DOUBLE_EQ(cells.cell_size, cell);
    std::uint32_t parts = 0;
    connected_components(build_neighbour_graph(cells, options), &parts);
    return parts;
  };
  EXPECT_EQ(parts_of(line(5, 1), g, grown), 3u);  // the line and the two pins
  EXPECT_EQ(parts_of(line(5, 3), g, grown), 8u);  // six pieces and the pins
  NeighbourGraphOptions off = g;
  off.sparse_occupancy = 0.0;
  EXPECT_EQ(parts_of(line(5, 1), off, grown), 8u);
  // On the plain cube (whole depths) the grid is the density rule's own: no widening.
  OctreeOptions plain;
  plain.depth = 4;
  PointCloud scaled = line(5, 1);
  for (auto& p : scaled.positions) p *= 1.25;  // the same cells, 1.25 wide, on a plain cube of 20
  const OctreeCells cells = build_octree_cells(scaled, plain);
  ASSERT_DOUBLE_EQ(cells.cell_size, cell);
  std::uint32_t parts = 0;
  connected_components(build_neighbour_graph(cells, g), &parts);
  EXPECT_EQ(parts, 8u);
}

TEST(NeighbourGraph, KnnGraphIsSymmetricWithAtLeastKNeighbours) {
  PointCloud cloud;
  for (int i = 0; i < 400; ++i) cloud.positions.emplace_back(std::cos(i * 0.1) * (1 + i * 0.01), std::sin(i * 0.1), i * 0.01);
  const OctreeCells cells = build_octree_cells(cloud, {});
  NeighbourGraphOptions g;
  g.mode = NeighbourMode::knn;
  g.k = 6;
  g.bridge_distance = -1.0;
  const CellGraph graph = build_neighbour_graph(cells, g);
  for (std::size_t c = 0; c < graph.vertex_count(); ++c) {
    EXPECT_GE(graph.offsets[c + 1] - graph.offsets[c], 6u);
    for (auto e = graph.offsets[c]; e < graph.offsets[c + 1]; ++e) EXPECT_NE(graph.targets[e], c);
  }
}

}  // namespace
}  // namespace treeskel
