#include "treeskel/modeling/tree_mesh.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/boost/graph/graph_traits_TriMesh_ArrayKernelT.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <iterator>
#include <stdexcept>
#include <sstream>

namespace treeskel::modeling {

namespace PMP = CGAL::Polygon_mesh_processing;

bool MeshCheck::ok() const { return problem().empty(); }

std::string MeshCheck::problem() const {
  std::ostringstream out;
  if (faces == 0) return "the mesh is empty";
  if (boundary_edges > 0) out << "the mesh is not closed (" << boundary_edges << " boundary edges)";
  else if (non_manifold_vertices > 0) out << non_manifold_vertices << " vertices are not manifold";
  else if (degenerate_faces > 0) out << degenerate_faces << " faces have zero area";
  else if (components != 1) out << "the mesh has " << components << " components";
  else if (!(volume > 0.0)) out << "the mesh's normals point inward (volume " << volume << ")";
  else if (self_intersections > 0) out << "the mesh intersects itself (" << self_intersections << " face pairs)";
  return out.str();
}

namespace {

/// A readable property map: a vertex's place, taken from a vector by the vertex's index.
struct Places {
  using key_type = TreeMesh::VertexHandle;
  using value_type = CGAL::Epick::Point_3;
  using reference = value_type;
  using category = boost::readable_property_map_tag;
  const std::vector<TreeMesh::Point>* places;
  friend value_type get(const Places& m, key_type v) {
    const auto& p = (*m.places)[static_cast<std::size_t>(v.idx())];
    return {p[0], p[1], p[2]};
  }
};

template <typename FaceRange, typename Parameters = CGAL::parameters::Default_named_parameters>
std::vector<std::pair<std::size_t, std::size_t>> crossing_pairs(const FaceRange& range, const TreeMesh& mesh,
                                                               const Parameters& np = CGAL::parameters::default_values()) {
  using Face = boost::graph_traits<TreeMesh>::face_descriptor;
  std::vector<std::pair<Face, Face>> pairs;
  PMP::self_intersections<CGAL::Parallel_if_available_tag>(range, mesh, std::back_inserter(pairs), np);
  std::vector<std::pair<std::size_t, std::size_t>> out;
  out.reserve(pairs.size());
  for (const auto& [a, b] : pairs) out.emplace_back(static_cast<std::size_t>(a.idx()), static_cast<std::size_t>(b.idx()));
  return out;
}

/// The faces of `mesh` with the indices `among`.
std::vector<TreeMesh::FaceHandle> face_handles(const TreeMesh& mesh, const std::vector<std::size_t>& among) {
  std::vector<TreeMesh::FaceHandle> out;
  out.reserve(among.size());
  for (std::size_t f : among) out.push_back(mesh.face_handle(static_cast<unsigned>(f)));
  return out;
}

}  // namespace

std::vector<std::pair<std::size_t, std::size_t>> self_intersecting_faces(const TreeMesh& mesh) {
  return crossing_pairs(faces(mesh), mesh);
}

std::vector<std::pair<std::size_t, std::size_t>> self_intersecting_faces(const TreeMesh& mesh,
                                                                        const std::vector<std::size_t>& among) {
  return crossing_pairs(face_handles(mesh, among), mesh);
}

std::vector<std::pair<std::size_t, std::size_t>> self_intersecting_faces_at(const TreeMesh& mesh,
                                                                           const std::vector<TreeMesh::Point>& places,
                                                                           const std::vector<std::size_t>* among) {
  if (places.size() != mesh.n_vertices()) throw std::invalid_argument("self_intersecting_faces_at: one place per vertex");
  const auto np = CGAL::parameters::vertex_point_map(Places{&places});
  if (!among) return crossing_pairs(faces(mesh), mesh, np);
  return crossing_pairs(face_handles(mesh, *among), mesh, np);
}

MeshCheck check_mesh(const TreeMesh& mesh, bool self_intersections) {
  MeshCheck c;
  c.vertices = mesh.n_vertices();
  c.faces = mesh.n_faces();
  if (c.faces == 0) return c;
  for (auto e : mesh.edges())
    if (mesh.is_boundary(e)) ++c.boundary_edges;
  std::vector<std::size_t> incident(mesh.n_vertices(), 0);
  for (auto f : mesh.faces())
    for (auto v : mesh.fv_range(f)) ++incident[static_cast<std::size_t>(v.idx())];
  for (auto v : mesh.vertices()) {
    std::size_t fan = 0;
    for (auto f : mesh.vf_range(v)) {
      (void)f;
      ++fan;
    }
    if (fan != incident[static_cast<std::size_t>(v.idx())]) ++c.non_manifold_vertices;
  }
  for (auto f : mesh.faces()) {
    auto it = mesh.cfv_begin(f);
    const auto a = mesh.point(*it++), b = mesh.point(*it++), d = mesh.point(*it);
    if (OpenMesh::cross(b - a, d - a).sqrnorm() == 0.0) ++c.degenerate_faces;
  }
  {
    // Components by a breadth-first walk over faces sharing an edge.
    std::vector<bool> seen(mesh.n_faces(), false);
    std::vector<TreeMesh::FaceHandle> stack;
    for (auto f : mesh.faces()) {
      if (seen[static_cast<std::size_t>(f.idx())]) continue;
      ++c.components;
      seen[static_cast<std::size_t>(f.idx())] = true;
      stack.push_back(f);
      while (!stack.empty()) {
        const auto g = stack.back();
        stack.pop_back();
        for (auto h : mesh.ff_range(g))
          if (!seen[static_cast<std::size_t>(h.idx())]) {
            seen[static_cast<std::size_t>(h.idx())] = true;
            stack.push_back(h);
          }
      }
    }
  }
  c.area = PMP::area(mesh);
  if (c.boundary_edges == 0) c.volume = PMP::volume(mesh);
  if (self_intersections) {
    c.self_intersections = self_intersecting_faces(mesh).size();
    c.self_intersections_checked = true;
  }
  return c;
}

}  // namespace treeskel::modeling
