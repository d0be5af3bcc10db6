#include "mesh_union.h"

#include "surface_mesh.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/intersection.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Random.h>
#include <CGAL/Surface_mesh.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <numeric>

namespace treeskel::modeling::detail {

namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
// Exact constructions: the points where two surfaces cross are kept exactly through every union (with
// rounded ones, a union can cross itself and the next one fail); they are rounded once at the end.
using K = CGAL::Exact_predicates_exact_constructions_kernel;
using Surface = CGAL::Surface_mesh<K::Point_3>;

void append(Surface& out, const TreeMesh& mesh) { append_to_surface(out, mesh); }

/// The mesh with its points rounded to 32-bit floats in the frame `offset` leads to, in a canonical
/// order (vertices by position, faces by their vertices): corefinement's own order differs from run
/// to run, the result must not.
TreeMesh to_tree_mesh(const Surface& s, const Eigen::Vector3d& offset) {
  std::vector<std::array<double, 3>> points;
  std::vector<Surface::Vertex_index> ids;
  for (auto v : s.vertices()) {
    const auto& p = s.point(v);
    const Eigen::Vector3d exact(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
    std::array<double, 3> q;
    for (int a = 0; a < 3; ++a)
      q[static_cast<std::size_t>(a)] = static_cast<double>(static_cast<float>(exact[a] + offset[a])) - offset[a];
    points.push_back(q);
    ids.push_back(v);
  }
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return points[a] < points[b]; });
  std::vector<std::size_t> rank(s.number_of_vertices() + s.number_of_removed_vertices());
  for (std::size_t k = 0; k < order.size(); ++k) rank[ids[order[k]]] = k;
  std::vector<std::array<std::size_t, 3>> faces;
  for (auto f : s.faces()) {
    std::array<std::size_t, 3> c{};
    std::size_t k = 0;
    for (auto v : CGAL::vertices_around_face(s.halfedge(f), s)) {
      if (k == 3) break;
      c[k++] = rank[v];
    }
    std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());  // orientation kept
    faces.push_back(c);
  }
  std::sort(faces.begin(), faces.end());
  TreeMesh out;
  std::vector<TreeMesh::VertexHandle> handle;
  for (std::size_t k : order) handle.push_back(out.add_vertex(TreeMesh::Point(points[k][0], points[k][1], points[k][2])));
  for (const auto& c : faces) out.add_face(handle[c[0]], handle[c[1]], handle[c[2]]);
  return out;
}

Eigen::AlignedBox3d box_of(const TreeMesh& mesh) {
  Eigen::AlignedBox3d box;
  for (auto v : mesh.vertices()) {
    const auto p = mesh.point(v);
    box.extend(Eigen::Vector3d(p[0], p[1], p[2]));
  }
  return box;
}

/// Corefines `piece` into `whole` (their union replaces `whole`); false, with `whole` unchanged, if
/// CGAL refuses.
bool unite_into(Surface& whole, Surface piece) {
  Surface result;
  bool ok = false;
  try {
    Surface copy = whole;
    ok = PMP::corefine_and_compute_union(copy, piece, result);
  } catch (const std::exception&) {
    ok = false;
  }
  if (ok) whole = std::move(result);
  return ok;
}

}  // namespace

/// Whether moving `from` and `to` onto `mid` would turn one of their faces (other than the two the
/// collapse removes, and slivers no taller than `weld`) by more than 60 degrees: such a collapse
/// could fold the surface into itself.
static bool turns_a_face(const TreeMesh& mesh, TreeMesh::VertexHandle from, TreeMesh::VertexHandle to,
                         const TreeMesh::Point& mid, double weld) {
  for (const auto v : {from, to})
    for (auto f : mesh.vf_range(v)) {
      std::array<TreeMesh::Point, 3> before, after;
      std::size_t k = 0;
      bool removed = false;
      for (auto u : mesh.fv_range(f)) {
        before[k] = mesh.point(u);
        after[k] = (u == from || u == to) ? mid : mesh.point(u);
        removed = removed || (u == (v == from ? to : from));
        ++k;
      }
      if (removed) continue;
      const auto n0 = OpenMesh::cross(before[1] - before[0], before[2] - before[0]);
      const auto n1 = OpenMesh::cross(after[1] - after[0], after[2] - after[0]);
      const double l0 = n0.norm(), l1 = n1.norm();
      // A sliver no taller than the weld distance has no direction to keep.
      const double longest = std::max({(before[1] - before[0]).norm(), (before[2] - before[1]).norm(), (before[0] - before[2]).norm()});
      if (l0 <= weld * longest) continue;
      if (l1 == 0.0 || OpenMesh::dot(n0, n1) < 0.5 * l0 * l1) return true;
    }
  return false;
}


namespace {

/// Collapses edge `e` onto one of its ends if that keeps the mesh manifold and turns no face over.
bool collapse_edge(TreeMesh& mesh, TreeMesh::EdgeHandle e, double weld) {
  for (int side = 0; side < 2; ++side) {
    const auto h = mesh.halfedge_handle(e, side);
    if (!mesh.is_collapse_ok(h)) continue;
    const auto from = mesh.from_vertex_handle(h), to = mesh.to_vertex_handle(h);
    if (turns_a_face(mesh, from, to, mesh.point(to), weld)) continue;
    mesh.collapse(h);
    return true;
  }
  return false;
}

}  // namespace

std::size_t collapse_shortest_edges(TreeMesh& mesh, const std::vector<std::size_t>& faces, double max_length) {
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_face_status();
  std::size_t done = 0;
  for (std::size_t f : faces) {
    const auto fh = mesh.face_handle(static_cast<unsigned>(f));
    if (!fh.is_valid() || mesh.status(fh).deleted()) continue;
    TreeMesh::EdgeHandle shortest;
    double best = max_length * max_length;
    for (auto h : mesh.fh_range(fh)) {
      const double l = mesh.calc_edge_sqr_length(mesh.edge_handle(h));
      if (l <= best) {
        best = l;
        shortest = mesh.edge_handle(h);
      }
    }
    if (shortest.is_valid() && collapse_edge(mesh, shortest, 0.0)) ++done;
  }
  mesh.garbage_collection();
  return done;
}

std::size_t weld_short_edges(TreeMesh& mesh, double weld) {
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_face_status();
  std::size_t welded = 0;
  const double weld2 = weld * weld;
  for (bool again = true; again;) {
    again = false;
    for (auto e : mesh.edges()) {
      if (mesh.status(e).deleted() || mesh.calc_edge_sqr_length(e) > weld2) continue;
      // Onto the end that stays (vertices keep their rounded coordinates).
      const bool done = collapse_edge(mesh, e, weld);
      if (!done) continue;
      ++welded;
      again = true;
    }
  }
  mesh.garbage_collection();
  return welded;
}

UnionResult unite(const TreeMesh& base, const std::vector<TreeMesh>& pieces, double weld, const Eigen::Vector3d& offset) {
  // Box intersection (inside corefinement) shuffles with CGAL's default random generator: seeded
  // here, the same input gives the same mesh.
  CGAL::get_default_random() = CGAL::Random(0);
  UnionResult out;
  Surface whole;
  append(whole, base);
  // Batches of pieces whose boxes (grown by a hair) overlap no other piece of the batch.
  std::vector<Eigen::AlignedBox3d> boxes;
  for (const auto& p : pieces) {
    Eigen::AlignedBox3d b = box_of(p);
    const double grow = 1e-6 * std::max(b.sizes().maxCoeff(), 1e-300);
    b.min().array() -= grow;
    b.max().array() += grow;
    boxes.push_back(b);
  }
  // Batches of pieces that neither cross nor hold one another: each batch is one corefinement
  // with the whole (whose cost grows with the whole's size, not the batch's).
  std::vector<std::vector<std::size_t>> batches;
  std::vector<std::size_t> refused;
  std::vector<Surface> surfaces(pieces.size());
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    // Corefinement needs closed inputs free of self-intersections (CGAL may crash otherwise).
    append(surfaces[i], pieces[i]);
    if (!CGAL::is_closed(surfaces[i]) || PMP::does_self_intersect(surfaces[i])) {
      refused.push_back(i);
      continue;
    }
    bool placed = false;
    for (auto& batch : batches) {
      bool clear = true;
      for (std::size_t j : batch)
        if (boxes[i].intersects(boxes[j]) &&
            PMP::do_intersect(surfaces[i], surfaces[j], CGAL::parameters::do_overlap_test_of_bounded_sides(true),
                              CGAL::parameters::do_overlap_test_of_bounded_sides(true))) {
          clear = false;
          break;
        }
      if (!clear) continue;
      batch.push_back(i);
      placed = true;
      break;
    }
    if (!placed) batches.push_back({i});
  }
  for (const auto& batch : batches) {
    Surface together;
    for (std::size_t i : batch) together.join(surfaces[i]);
    ++out.batches;
    if (unite_into(whole, std::move(together))) {
        out.united += batch.size();
      continue;
    }
    for (std::size_t i : batch) {
      if (batch.size() > 1) ++out.batches;
      if (batch.size() > 1 && unite_into(whole, surfaces[i])) ++out.united;
      else refused.push_back(i);
    }
  }
  // A refused piece is kept beside the mesh: its triangles are added as they are.
  for (std::size_t i : refused) {
    whole.join(surfaces[i]);
    ++out.failed;
  }
  whole.collect_garbage();
  // The exact points rounded to what 32-bit floats hold in the input's frame, where most formats and
  // MeshLab keep them: a file then holds the mesh that was checked.
  out.mesh = to_tree_mesh(whole, offset);
  if (out.batches > 0) {
    out.welded = weld_short_edges(out.mesh, weld);
  }
  return out;
}

}  // namespace treeskel::modeling::detail
