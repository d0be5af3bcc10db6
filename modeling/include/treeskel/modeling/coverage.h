/// @file coverage.h
/// How much of a tree a mesh shows: the share of the skeleton's length inside the mesh, and the share
/// of a cloud's points near the mesh's surface. A mesh can be closed, manifold and free of
/// self-intersections and still leave out half the tree; these numbers say so.
#pragma once

#include "treeskel/modeling/tree_mesh.h"
#include "treeskel/point_cloud.h"
#include "treeskel/skeleton.h"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace treeskel::modeling {

/// What `wood_inside` found.
struct WoodInside {
  double volume = 0.0;       ///< the frustums between the skeleton's nodes, with their radii
  std::size_t samples = 0;   ///< points drawn in them
  std::size_t inside = 0;    ///< of those, inside the mesh or on its surface
  double share() const { return samples > 0 ? static_cast<double>(inside) / static_cast<double>(samples) : 1.0; }
};

/// The points `wood_inside` draws unless told otherwise: the share to about ±0.01 (one standard
/// deviation of a share near 0.9 is 0.005).
inline constexpr std::size_t kWoodSamples = 4000;

/// How much of the wood the skeleton's radii describe lies inside the mesh: `samples` points drawn
/// uniformly in the volume of the frustums between the skeleton's nodes (the volume `measure_tree`
/// reports), each tested against the mesh. The mesh's volume over the frustums' cannot tell wood the
/// mesh lacks from frustums that overlap (a branch's first segment inside its parent, a path that
/// folds back), which that ratio counts twice; this share can: an overlap is inside the mesh too.
/// Seeded by `seed`: the same share every run, for any number of threads.
/// @pre `mesh` is closed (its inside is then defined).
WoodInside wood_inside(const Skeleton& skeleton, const TreeMesh& mesh, std::size_t samples = kWoodSamples,
                       std::uint64_t seed = 1);

/// What `skeleton_coverage` found: how much of the skeleton's length, and of the wood its radii
/// describe, the mesh holds.
struct SkeletonCoverage {
  double length = 0.0;          ///< total length of the skeleton's edges
  double inside_length = 0.0;   ///< of which inside the mesh (or on its surface)
  WoodInside wood;              ///< the frustums' wood inside the mesh (`wood_inside`)
  double share() const { return length > 0.0 ? inside_length / length : 1.0; }
};

/// Cuts every skeleton edge into pieces at most `step` long (at least two) and tests each piece's
/// centre, which stands for the piece's length: covered when it lies inside the closed mesh or
/// within `tolerance` of its surface. Measures the wood inside too (`wood_inside` with seed 1), on
/// the same search structure.
/// @param[in] step          sample spacing along the edges (input units); 0: 1/2000 of the skeleton's extent
/// @param[in] tolerance     distance from the surface that still counts as covered; 0: 1e-6 of the extent
/// @param[in] wood_samples  the points `wood_inside` draws; 0 leaves the wood unmeasured (`wood.samples` 0)
/// @pre `mesh` is closed (its inside is then defined).
SkeletonCoverage skeleton_coverage(const Skeleton& skeleton, const TreeMesh& mesh, double step = 0.0,
                                   double tolerance = 0.0, std::size_t wood_samples = kWoodSamples);

/// Distance from each point to the mesh's surface (exact, by an AABB tree over the triangles).
std::vector<double> surface_distances(const TreeMesh& mesh, const std::vector<Eigen::Vector3d>& points);

/// The share of `distances` at most `limit`.
double share_within(const std::vector<double>& distances, double limit);

}  // namespace treeskel::modeling
