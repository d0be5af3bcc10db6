/// @file geodesic.h
/// Geodesic distance from the root on the neighbour graph (Fu et al. 2020, section IV.B), by
/// Dijkstra's algorithm, and the choice of the root.
#pragma once

#include "treeskel/neighbour_graph.h"
#include "treeskel/octree.h"

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <vector>

namespace treeskel {

struct RootOptions {
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  ///< the tree grows along this direction
  /// Where the tree stands, in the local frame. Unset (default): at the lowest skeleton point.
  std::optional<Eigen::Vector3d> point;
  /// The root is the slice of the trunk base this thick along `up`, so that the level sets start as
  /// level cuts through the trunk. 0 (default): two cell sizes (one band).
  double slice = 0.0;
};

/// Geodesic distance of every cell from the root cells.
struct GeodesicField {
  std::vector<double> distance;            ///< +infinity where the cell is not reached
  std::vector<std::int64_t> predecessor;   ///< previous cell on a shortest path; -1 for roots and unreached
};

/// The root slice thickness `options` give for these cells: `slice`, or 2 cell sizes when it is 0.
double root_slice_for(const RootOptions& options, const OctreeCells& cells);

/// The cells the geodesic distance starts from: the lowest slice of the tree (the part of it that is
/// connected to the lowest cell), or the cell nearest to `options.point`.
/// @pre at least one cell is in the tree.
std::vector<std::uint32_t> select_root_cells(const OctreeCells& cells, const CellGraph& graph,
                                             const std::vector<bool>& in_tree, const RootOptions& options = {});

/// Shortest-path distances from the nearest of `sources` (multi-source Dijkstra). Ties are broken
/// the same way every time: of two cells at the same distance the lower index is settled first, and
/// a cell's predecessor is the first settled cell that gives it its distance.
GeodesicField geodesic_distance(const CellGraph& graph, const std::vector<std::uint32_t>& sources);

}  // namespace treeskel
