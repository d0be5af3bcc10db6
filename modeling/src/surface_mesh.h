// A tree mesh as a CGAL Surface_mesh of any kernel, for the CGAL algorithms that want one (AABB
// trees, corefinement).
#pragma once

#include "treeskel/modeling/tree_mesh.h"

#include <array>
#include <cstddef>
#include <vector>

namespace treeskel::modeling::detail {

/// Appends the vertices and triangles of `mesh` to `out` (whose other contents stay).
template <class Surface>
void append_to_surface(Surface& out, const TreeMesh& mesh) {
  using Point = typename Surface::Point;
  using Vertex = typename Surface::Vertex_index;
  std::vector<Vertex> handle;
  handle.reserve(mesh.n_vertices());
  for (auto v : mesh.vertices()) {
    const auto p = mesh.point(v);
    handle.push_back(out.add_vertex(Point(p[0], p[1], p[2])));
  }
  for (auto f : mesh.faces()) {
    std::array<Vertex, 3> c;
    std::size_t k = 0;
    for (auto v : mesh.fv_range(f)) c[k++] = handle[static_cast<std::size_t>(v.idx())];
    out.add_face(c[0], c[1], c[2]);
  }
}

}  // namespace treeskel::modeling::detail
