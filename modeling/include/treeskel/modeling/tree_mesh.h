/// @file tree_mesh.h
/// The triangle mesh type of tree models (OpenMesh, double precision) and its validity checks
/// (CGAL Polygon Mesh Processing): closed, 2-manifold, outward, free of self-intersections.
#pragma once

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace treeskel::modeling {

struct MeshTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};
/// Triangle mesh of a tree model, in the skeleton's local frame (add the skeleton's offset for world
/// coordinates).
using TreeMesh = OpenMesh::TriMesh_ArrayKernelT<MeshTraits>;

/// What `check_mesh` found.
struct MeshCheck {
  std::size_t vertices = 0;
  std::size_t faces = 0;
  std::size_t boundary_edges = 0;          ///< 0 for a closed mesh
  std::size_t non_manifold_vertices = 0;   ///< vertices whose faces form more than one fan
  std::size_t degenerate_faces = 0;        ///< faces of zero area
  std::size_t self_intersections = 0;      ///< pairs of faces that intersect (not counting shared edges)
  std::size_t components = 0;              ///< connected components
  double volume = 0.0;                     ///< signed volume (positive when the normals point outward)
  double area = 0.0;
  bool self_intersections_checked = false;

  /// True for one closed, manifold, outward, self-intersection-free component with no degenerate face.
  bool ok() const;
  /// A sentence naming the first problem, or an empty string.
  std::string problem() const;
};

/// Checks a tree mesh. Non-manifold edges cannot exist in an OpenMesh mesh (it refuses such faces).
/// @param[in] self_intersections  also run the self-intersection test (the costly part)
MeshCheck check_mesh(const TreeMesh& mesh, bool self_intersections = true);

/// Pairs of faces (by index) that intersect each other; faces sharing an edge or a vertex only along
/// it do not count.
std::vector<std::pair<std::size_t, std::size_t>> self_intersecting_faces(const TreeMesh& mesh);

/// The same among the faces `among` (indices) only: pairs of two of them. Where a change to a mesh
/// is confined to a region, testing the faces there is enough to tell whether it added a crossing.
std::vector<std::pair<std::size_t, std::size_t>> self_intersecting_faces(const TreeMesh& mesh,
                                                                        const std::vector<std::size_t>& among);

/// The same with the vertices placed at `places` (by vertex index) instead of their points, among
/// the faces `among` if given: for example at the 32-bit floats a file rounds them to, without
/// copying the mesh.
std::vector<std::pair<std::size_t, std::size_t>> self_intersecting_faces_at(const TreeMesh& mesh,
                                                                           const std::vector<TreeMesh::Point>& places,
                                                                           const std::vector<std::size_t>* among = nullptr);

}  // namespace treeskel::modeling
