/// @file point_cloud.h
/// The point cloud treeskel works on.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace treeskel {

/// A raw scan. Positions are stored in a local frame: `world = position + offset`. Readers choose the
/// offset (the minimum corner of the bounding box) so that georeferenced clouds, which sit around
/// x = 300,000 and y = 5,000,000 in UTM, are computed on small numbers and every result is independent
/// of where the tree stands. Writers add the offset back.
struct PointCloud {
  std::vector<Eigen::Vector3d> positions;       ///< local coordinates, in the input's units
  std::vector<Eigen::Vector3f> normals;         ///< empty, or one per point
  std::vector<std::array<std::uint8_t, 3>> colors;  ///< empty, or one RGB per point
  /// Empty, or one ASPRS class per point as a LAS file gives it (2 ground, 3-5 vegetation, ...); the
  /// LAS reader fills it when any point has a class other than 0 and 1 (never classified, unclassified).
  std::vector<std::uint8_t> classes;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  ///< added to a local position to get the input's frame

  std::size_t size() const { return positions.size(); }
  bool empty() const { return positions.empty(); }
  bool has_normals() const { return !normals.empty(); }
  bool has_colors() const { return !colors.empty(); }
};

/// Appends point `p` of `from` to `to`: its position, and its normal, colour and class where `from` has
/// them (`to` takes the points of one cloud only, and its offset).
void append_point(PointCloud& to, const PointCloud& from, std::size_t p);

/// Axis-aligned bounding box of the local positions (empty box for an empty cloud).
Eigen::AlignedBox3d bounding_box(const PointCloud& cloud);

/// Moves the cloud's local frame so that its bounding box starts at the origin: the positions lose the
/// box's minimum corner and `offset` gains it. World coordinates are unchanged.
void recentre_offset(PointCloud& cloud);

/// Shape of the cloud as the method sees it.
enum class CloudShape { ok, empty, identical, collinear };

/// Classifies a cloud: no points, all points at one place, or all points on one line (the second
/// principal extent is below `relative_tolerance` times the first).
CloudShape classify_shape(const PointCloud& cloud, double relative_tolerance = 1e-6);

}  // namespace treeskel
