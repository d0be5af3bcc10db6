/// @file octree.h
/// Octree subdivision of the cloud and one L1-median per non-empty leaf cell: the initial skeleton
/// points of Fu et al. 2020, section IV.A. The leaves of a complete octree of depth d are the cells of a
/// regular 2^d grid over the cloud's bounding cube, so they are found by sorting points on their
/// Morton key instead of building the tree level by level; the result is the same set of cells.
#pragma once

#include "treeskel/l1_median.h"
#include "treeskel/point_cloud.h"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace treeskel {

struct OctreeOptions {
  /// Subdivision depth in [1, 21]. 0 (default): chosen from the data, see `points_per_cell`.
  int depth = 0;
  /// With depth 0, the deepest depth at which the cell of a typical point (the point-weighted median
  /// of the cell populations, blind to lone outliers) holds at least this many points, but no deeper
  /// than `max_extra_depth` beyond the paper's `2 + log8 N`. The paper's fixed depth leaves ~1 point
  /// per cell on sparsely sampled stems, whose level sets then fall apart, or many on dense clouds of
  /// thin twigs, which it cannot resolve; a density target works for both. The default, 1, is met
  /// at every depth, so the depth is the cap: on sparse crowns a target of 2 made cells of 10 cm on a
  /// 10 m tree, and a clump of twigs half a metre across one node (docs/models.md, coverage). Dense
  /// clouds reach the cap with either.
  /// 0: the paper's depth, ⌊2 + log8 N⌋.
  double points_per_cell = 1.0;
  int max_extra_depth = 1;
  /// With depth 0, also try the cube grown by 2^(k / depth_steps), k = 1 .. depth_steps - 1, whose
  /// depths give cell sizes between two of the plain cube's; the finest cell that holds
  /// `points_per_cell` wins, under the depth cap taken unrounded (2 + log8 N + max_extra_depth
  /// levels). The whole depths alone make the cell jump by 2 with the point count (a crowded crown of
  /// 23k points got cells twice those of one of 46k, and half its forks): finer cells resolve close
  /// forks (docs/accuracy.md). 1: whole depths only.
  int depth_steps = 4;
  /// The grown cubes are tried for clouds of at most this many distinct points. Denser clouds already
  /// have cells far finer than their branches, and there the finer grid cost 40-55% more time.
  std::size_t depth_steps_max_points = 250000;
  /// With depth > 0: the cube is the points' bounding cube grown by this factor, in [1, 2] (what
  /// `automatic_options` pins beside the depth it chose).
  double cube_scale = 1.0;
  /// Points farther than this many times the extent of the cloud's bulk outside it are left out of
  /// the octree (and of the skeleton, as noise), so that one stray point cannot coarsen the grid.
  /// The bulk: per axis, the range between the 0.1% and 99.9% quantiles. 0 keeps every point.
  double outlier_distance = 0.5;
  L1MedianOptions median;  ///< Weiszfeld settings for the per-cell L1-medians
};

/// The non-empty leaf cells of the octree, ordered by Morton key.
struct OctreeCells {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< minimum corner of the bounding cube
  double cube_size = 0.0;                            ///< side of the bounding cube
  double cube_scale = 1.0;                           ///< cube_size over the points' bounding cube's side (> 1: a grown cube)
  int depth = 0;                                     ///< subdivision depth
  double cell_size = 0.0;                            ///< side of a leaf cell: cube_size / 2^depth
  std::vector<std::uint64_t> keys;                   ///< Morton key per cell, strictly increasing
  std::vector<std::uint32_t> first;                  ///< cell c owns point_order[first[c], first[c+1])
  std::vector<std::uint32_t> point_order;            ///< point indices grouped by cell
  std::vector<Eigen::Vector3d> medians;              ///< L1-median of each cell's points
  std::vector<std::uint32_t> outliers;               ///< points far outside the cloud's bulk, in no cell
  /// Every point at the very place of a point with a lower index (the same coordinates, -0 and +0
  /// alike), as (point, the lowest index at that place), by point. Such a point is still in its cell.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> repeats;

  std::size_t cell_count() const { return keys.size(); }
  const std::uint32_t* begin(std::size_t cell) const { return point_order.data() + first[cell]; }
  const std::uint32_t* end(std::size_t cell) const { return point_order.data() + first[cell + 1]; }
  std::size_t point_count(std::size_t cell) const { return first[cell + 1] - first[cell]; }
  /// Integer grid coordinates of a cell.
  Eigen::Vector3i coordinates(std::size_t cell) const;
  /// Index of the cell with these grid coordinates, or -1 when it is empty or outside the grid.
  std::int64_t find(const Eigen::Vector3i& coordinates) const;
};

/// The paper's default depth `2 + log8 n`, rounded down, kept in [1, 21].
int paper_octree_depth(std::size_t point_count);

/// Interleaves the low 21 bits of x, y and z.
std::uint64_t morton_encode(std::uint32_t x, std::uint32_t y, std::uint32_t z);
/// Inverse of morton_encode.
Eigen::Vector3i morton_decode(std::uint64_t key);

/// Subdivides the cloud and computes the per-cell L1-medians (in parallel, deterministic). The cube
/// bounds the points that are not outliers; the depth counts repeated points once (a cloud with
/// every point written twice gives the same cells).
/// @throws InputError for an empty cloud.
OctreeCells build_octree_cells(const PointCloud& cloud, const OctreeOptions& options = {});

/// `build_octree_cells` without the medians (`medians` stays empty): the cells, outliers and repeats
/// alone, for a caller that may not need the medians (a cloud with repeats is skeletonized from its
/// distinct points). `compute_cell_medians` completes it.
/// @throws InputError for an empty cloud.
OctreeCells partition_octree(const PointCloud& cloud, const OctreeOptions& options = {});

/// Fills `cells.medians` with the L1-median of each cell's points (in parallel, deterministic).
void compute_cell_medians(OctreeCells& cells, const PointCloud& cloud, const L1MedianOptions& options = {});

}  // namespace treeskel
