// The convex hull of a join's points, triangulated the same way on every run.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <vector>

namespace treeskel::modeling::detail {

/// The faces of the convex hull of `points`, each three indices into `points`, outward by the
/// right-hand rule. A point given twice stands for itself by its last index. `group` (one label per
/// point, or empty: each point its own) names the polygons the hull is built around, a join's
/// rings: a group that lies in a face of the hull keeps its own polygon there, covered by triangles
/// of its points alone, and no other triangle has all its corners in one group.
///
/// CGAL's hull splits a face that holds four or more points (a quad between two parallel rings, a
/// ring in the plane of another's points) into triangles in an order that follows the memory
/// addresses of its working triangulation: the same points gave two meshes from run to run when
/// other threads had run before. Each such flat region is triangulated here again: cut along the
/// edges of the groups' polygons (the lowest pair first), and each convex piece fanned from its
/// lowest index, so the faces depend on the points alone. (A point in line with two corners is no
/// corner, so a fan cannot degenerate; it is checked anyway, and a fan that would tries the next
/// index.) A region that is not one convex polygon, or has a piece no fan fits (neither met on
/// hulls, but not ruled out), keeps CGAL's triangles.
std::vector<std::array<std::size_t, 3>> convex_hull_faces(const std::vector<Eigen::Vector3d>& points,
                                                          const std::vector<std::size_t>& group = {});

}  // namespace treeskel::modeling::detail
