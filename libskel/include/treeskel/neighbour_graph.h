/// @file neighbour_graph.h
/// The neighbour graph on the octree's skeleton points (Fu et al. 2020, section IV.B), the bridging of
/// gaps that occlusion leaves between parts of a real scan, and the choice of the part that is the tree.
#pragma once

#include "treeskel/octree.h"
#include "treeskel/skeleton.h"

#include <cstdint>
#include <vector>

namespace treeskel {

enum class NeighbourMode {
  octree,  ///< cells that share a face, an edge or a corner (the paper's O(n) construction)
  knn,     ///< the k nearest skeleton points, symmetrised (CGAL spatial search)
};

struct NeighbourGraphOptions {
  NeighbourMode mode = NeighbourMode::octree;
  int k = 26;  ///< neighbours per skeleton point in `knn` mode
  /// In `octree` mode, cells up to this many cells apart along each axis are neighbours: 1 is the
  /// paper's 26-neighbourhood; 2 (124 neighbours) keeps sparsely sampled surfaces connected.
  int reach = 1;
  /// On a grown cube (cells finer than a whole depth gives; OctreeOptions::depth_steps), cells whose
  /// 3x3x3 neighbourhood holds on average fewer points a cell than this are also neighbours of such
  /// cells two cells apart: where the points are sparse for the finer grid (a thick limb scanned
  /// thinly), a band's ring holds together instead of falling into arcs that read as forks, while
  /// dense parts keep the fine grid. 0: never.
  double sparse_occupancy = 2.0;
  /// Parts of the graph whose closest skeleton points are at most this far apart are joined by an
  /// edge (occlusion gaps). 0 (default): 4 cell sizes. Negative: never bridge.
  double bridge_distance = 0.0;
  /// Parts that hold at least `far_bridge_min_points` points and at least `far_bridge_fraction` of
  /// the cloud are also joined across gaps up to this long, to another such part (a branch or a twig
  /// cut off by an occlusion); smaller parts are not, so a few stray points do not become branches.
  /// 0 (default): a tenth of the cloud's size. Negative: no far bridging.
  double far_bridge_distance = 0.0;
  /// The default joins a twig piece of two points (a far link still needs such a part at both ends,
  /// so a lone stray point stays out): on real scans most of what a larger floor left out were such
  /// pieces, the last twigs of sparse crowns (AdTree's tree33 reaches its top with 2, 0.88 of its
  /// height with 10; tree13 leaves 218 points out instead of 441 with 3), and the synthetic sets
  /// score within 0.01 of a floor of 3 (docs/models.md, "Far bridging of smaller parts").
  std::size_t far_bridge_min_points = 2;
  double far_bridge_fraction = 0.0;
  /// Bridging runs in rounds: each part not joined to the tree (the largest part) yet links to the
  /// nearest other part its probes meet, the parts joined so far counting as one, until a round
  /// joins nothing or this many have run. With 1 (before 5 December 2026), pieces of a crown that an
  /// occlusion cut off, nearer one another than the tree, joined one another and not the tree: the
  /// benchmark's tree2_missing_2 left 45% of its points out (README, Accuracy).
  std::size_t bridge_rounds = 16;
  /// After bridging, a part that is not the tree and holds fewer than this share of the points is
  /// reported as a small isolated cluster (noise); a larger one as a far part. Both are left out.
  double small_cluster_fraction = 0.01;
};

/// Symmetric weighted graph on the octree cells in compressed rows: the neighbours of cell c are
/// `targets[offsets[c] .. offsets[c+1])` at distances `weights[...]` between the cells' medians.
struct CellGraph {
  std::vector<std::uint32_t> offsets;
  std::vector<std::uint32_t> targets;
  std::vector<double> weights;
  std::size_t bridges = 0;  ///< edges added to bridge gaps between parts

  std::size_t vertex_count() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  std::size_t edge_count() const { return targets.size() / 2; }
};

/// Builds the neighbour graph on the cells' medians and bridges gaps between its parts.
/// The bridging distance `options` give for these cells: `bridge_distance`, or 4 cell sizes when it is 0.
double bridge_distance_for(const NeighbourGraphOptions& options, const OctreeCells& cells);

CellGraph build_neighbour_graph(const OctreeCells& cells, const NeighbourGraphOptions& options = {});

/// Connected components of the graph: a component id per cell, ids numbered from 0 in cell order.
std::vector<std::uint32_t> connected_components(const CellGraph& graph, std::uint32_t* count = nullptr);

/// The part of the graph that is the tree, and what is left out.
struct MainPart {
  std::vector<bool> in_tree;  ///< per cell
  LeftOut left_out;           ///< points of the other parts, by reason
  std::size_t parts = 0;      ///< connected parts after bridging
};

/// Picks the connected part holding the most points as the tree.
MainPart select_main_part(const OctreeCells& cells, const CellGraph& graph, const NeighbourGraphOptions& options = {});

}  // namespace treeskel
