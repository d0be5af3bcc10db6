#include "attempt.h"

#include "treeskel/geometry.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>
#include <Eigen/Geometry>

#include <algorithm>

namespace treeskel::modeling::detail {

std::optional<TreeMesh> assemble(Attempt& attempt) {
  const auto& vertices = attempt.vertices;
  const auto& faces = attempt.faces;
  TreeMesh mesh;
  std::vector<TreeMesh::VertexHandle> handles;
  handles.reserve(vertices.size());
  for (const auto& v : vertices) handles.push_back(mesh.add_vertex(TreeMesh::Point(v.x(), v.y(), v.z())));
  std::vector<NodeId> owners;
  std::vector<double> radii;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto h = mesh.add_face(handles[faces[f][0]], handles[faces[f][1]], handles[faces[f][2]]);
    if (!h.is_valid()) {
      attempt.shrink.push_back(attempt.face_owner[f]);
      continue;
    }
    owners.push_back(attempt.face_owner[f]);
    radii.push_back(attempt.owner_radius[f]);
  }
  attempt.face_owner = std::move(owners);
  attempt.owner_radius = std::move(radii);
  attempt.face_part.clear();  // no longer in step with the faces
  // Vertices no face uses (none expected) would make the mesh look open to some tools.
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_face_status();
  bool isolated = false;
  for (auto v : mesh.vertices())
    if (mesh.is_isolated(v)) {
      mesh.delete_vertex(v, false);
      isolated = true;
    }
  if (isolated) mesh.garbage_collection();
  if (!attempt.shrink.empty()) return std::nullopt;
  return mesh;
}

std::vector<std::pair<std::size_t, std::size_t>> crossing_parts(const Attempt& attempt) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t, CGAL::Box_intersection_d::ID_EXPLICIT>;
  const auto& faces = attempt.faces;
  const std::size_t parts = attempt.part_rings.size();
  std::vector<Eigen::AlignedBox3d> face_box(faces.size()), part_box(parts);
  std::vector<std::vector<std::size_t>> part_faces(parts);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    for (std::size_t v : faces[f]) face_box[f].extend(attempt.vertices[v]);
    part_box[attempt.face_part[f]].extend(face_box[f]);
    part_faces[attempt.face_part[f]].push_back(f);
  }
  std::vector<Box> boxes;
  boxes.reserve(parts);
  for (std::size_t i = 0; i < parts; ++i) {
    if (part_box[i].isEmpty()) continue;
    double lo[3], hi[3];
    for (int d = 0; d < 3; ++d) {
      lo[d] = part_box[i].min()[d];
      hi[d] = part_box[i].max()[d];
    }
    boxes.emplace_back(lo, hi, i);
  }
  std::vector<std::pair<std::size_t, std::size_t>> candidates;
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& x, const Box& y) {
    const auto& a = attempt.part_rings[x.info()];
    const auto& b = attempt.part_rings[y.info()];
    for (std::size_t ring : a)
      if (std::find(b.begin(), b.end(), ring) != b.end()) return;
    candidates.emplace_back(std::min(x.info(), y.info()), std::max(x.info(), y.info()));
  });
  std::sort(candidates.begin(), candidates.end());
  auto triangle = [&](std::size_t f) {
    const auto& v = attempt.vertices;
    auto point = [&](std::size_t i) { return K::Point_3(v[i].x(), v[i].y(), v[i].z()); };
    return K::Triangle_3(point(faces[f][0]), point(faces[f][1]), point(faces[f][2]));
  };
  std::vector<std::pair<std::size_t, std::size_t>> out;
  std::vector<std::size_t> near_a, near_b;
  for (const auto& [pa, pb] : candidates) {
    near_a.clear();
    near_b.clear();
    for (std::size_t f : part_faces[pa])
      if (face_box[f].intersects(part_box[pb])) near_a.push_back(f);
    for (std::size_t f : part_faces[pb])
      if (face_box[f].intersects(part_box[pa])) near_b.push_back(f);
    bool found = false;
    for (std::size_t fa : near_a) {
      for (std::size_t fb : near_b)
        if (face_box[fa].intersects(face_box[fb]) && CGAL::do_intersect(triangle(fa), triangle(fb))) {
          out.emplace_back(fa, fb);
          found = true;
          break;
        }
      if (found) break;
    }
  }
  return out;
}

std::optional<double> clearing_factor(const Attempt& attempt, std::size_t x, std::size_t y) {
  const auto& ax = attempt.part_axis[x];
  const auto& ay = attempt.part_axis[y];
  if (ax.tube < 0 || ay.tube < 0) return std::nullopt;
  auto factor = [](const Attempt::Axis& p, const Attempt::Axis& q) {
    return 0.97 * (segment_segment_distance(p.a, p.b, q.a, q.b) - q.radius) / p.radius;
  };
  double f = std::min(factor(ax, ay), 0.95);
  const auto& tx = attempt.tube_parts[static_cast<std::size_t>(ax.tube)];
  const auto& ty = attempt.tube_parts[static_cast<std::size_t>(ay.tube)];
  for (const std::ptrdiff_t j : tx.joins)
    if (j >= 0 && (j == ty.joins[0] || j == ty.joins[1])) return f;
  for (std::size_t p = tx.first_part; p < tx.end_part; ++p)
    for (std::size_t q = ty.first_part; q < ty.end_part; ++q)
      f = std::min(f, factor(attempt.part_axis[p], attempt.part_axis[q]));
  return f;
}

}  // namespace treeskel::modeling::detail
