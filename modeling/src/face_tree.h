// An AABB tree over a tree mesh's own triangles, in doubles (its points read where they are, not
// copied), and the side-of-mesh test over it: for the unions' tests and the coverage.
#pragma once

#include "treeskel/modeling/tree_mesh.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/boost/graph/graph_traits_TriMesh_ArrayKernelT.h>
// After the graph helpers above (Side_of_triangle_mesh needs them declared first).
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Side_of_triangle_mesh.h>

namespace treeskel::modeling::detail {

using GT = CGAL::Exact_predicates_inexact_constructions_kernel;
using VPM = boost::property_map<TreeMesh, CGAL::vertex_point_t>::const_type;
/// An AABB tree of a tree mesh's faces, in doubles.
using FaceTree = CGAL::AABB_tree<CGAL::AABB_traits<GT, CGAL::AABB_face_graph_triangle_primitive<TreeMesh, VPM>>>;
using SideOfFaces = CGAL::Side_of_triangle_mesh<TreeMesh, GT, VPM, FaceTree>;

}  // namespace treeskel::modeling::detail
