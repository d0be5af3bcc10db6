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
#include <vector>

namespace treeskel::modeling {

/// What `skeleton_coverage` found.
struct SkeletonCoverage {
  double length = 0.0;          ///< total length of the skeleton's edges
  double inside_length = 0.0;   ///< of which inside the mesh (or on its surface)
  double share() const { return length > 0.0 ? inside_length / length : 1.0; }
};

/// Cuts every skeleton edge into pieces at most `step` long (at least two) and tests each piece's
/// centre, which stands for the piece's length: covered when it lies inside the closed mesh or
/// within `tolerance` of its surface.
/// @param[in] step       sample spacing along the edges (input units); 0: 1/2000 of the skeleton's extent
/// @param[in] tolerance  distance from the surface that still counts as covered; 0: 1e-6 of the extent
/// @pre `mesh` is closed (its inside is then defined).
SkeletonCoverage skeleton_coverage(const Skeleton& skeleton, const TreeMesh& mesh, double step = 0.0,
                                   double tolerance = 0.0);

/// Distance from each point to the mesh's surface (exact, by an AABB tree over the triangles).
std::vector<double> surface_distances(const TreeMesh& mesh, const std::vector<Eigen::Vector3d>& points);

/// The share of `distances` at most `limit`.
double share_within(const std::vector<double>& distances, double limit);

}  // namespace treeskel::modeling
