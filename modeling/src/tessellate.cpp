#include "tessellate.h"

#include "hull.h"

#include <algorithm>

namespace treeskel::modeling::detail {

namespace {

using Eigen::Vector3d;

/// The faces of the convex hull of a join's rings and `extra` points, but the rings' own: the
/// join's surface. The last `optional` extra points may lie inside the hull (they are then left
/// out); any other point inside it means the rings do not fit, and `top` is to be thinned.
template <class AddFace>
void hull_faces(const std::vector<Ring>& rings, const std::vector<std::size_t>& first_vertex,
                const std::vector<std::pair<Vector3d, std::size_t>>& extra, std::size_t optional, NodeId top,
                double radius, HullCache& hulls, AddFace& add_face, Attempt& attempt) {
  // The join's points, and each one's vertex id and ring.
  std::vector<double> key;
  std::vector<std::size_t> id, ring_of;
  for (std::size_t i = 0; i < rings.size(); ++i)
    for (int k = 0; k < rings[i].sides; ++k) {
      const Vector3d p = rings[i].vertex(k);
      key.insert(key.end(), {p.x(), p.y(), p.z()});
      id.push_back(first_vertex[i] + static_cast<std::size_t>(k));
      ring_of.push_back(i);
    }
  for (std::size_t i = 0; i < extra.size(); ++i) {
    const Vector3d& p = extra[i].first;
    key.insert(key.end(), {p.x(), p.y(), p.z()});
    id.push_back(extra[i].second);
    ring_of.push_back(rings.size() + i);
  }
  const std::size_t required = id.size() - optional;
  key.push_back(static_cast<double>(optional));
  // Repair rounds leave most joins as they were: their hulls are computed once.
  auto cached = hulls.find(key);
  if (cached == hulls.end()) {
    std::vector<Vector3d> points;
    for (std::size_t i = 0; i < id.size(); ++i) points.emplace_back(key[3 * i], key[3 * i + 1], key[3 * i + 2]);
    auto faces = detail::convex_hull_faces(points, ring_of);
    std::vector<char> corner(points.size(), 0);
    for (const auto& f : faces)
      for (std::size_t i : f) corner[i] = 1;
    std::optional<std::vector<std::array<std::size_t, 3>>> corners;
    if (std::count(corner.begin(), corner.begin() + static_cast<std::ptrdiff_t>(required), 1) == static_cast<std::ptrdiff_t>(required))
      corners = std::move(faces);
    cached = hulls.emplace(std::move(key), std::move(corners)).first;
  }
  if (!cached->second) {  // points inside the hull: the rings do not fit
    attempt.shrink.push_back(top);
    return;
  }
  std::vector<std::array<std::size_t, 3>> triangles;
  for (const auto& corner : *cached->second) {
    if (ring_of[corner[0]] == ring_of[corner[1]] && ring_of[corner[1]] == ring_of[corner[2]]) continue;  // a ring's own face
    // Smallest vertex first, orientation kept: the hull's own face order is not canonical.
    std::array<std::size_t, 3> tri{id[corner[0]], id[corner[1]], id[corner[2]]};
    std::rotate(tri.begin(), std::min_element(tri.begin(), tri.end()), tri.end());
    triangles.push_back(tri);
  }
  std::sort(triangles.begin(), triangles.end());
  for (const auto& tri : triangles) add_face(tri[0], tri[1], tri[2], top, radius);
}

}  // namespace

std::size_t add_ring(std::vector<Vector3d>& vertices, const Ring& ring) {
  const std::size_t first = vertices.size();
  for (int k = 0; k < ring.sides; ++k) vertices.push_back(ring.vertex(k));
  return first;
}

void tessellate(const std::vector<Join>& joins, const std::vector<Tube>& tubes, HullCache& hulls, Attempt& attempt) {
  std::vector<Vector3d>& vertices = attempt.vertices;
  auto add_face = [&](std::size_t a, std::size_t b, std::size_t c, NodeId owner, double radius) {
    attempt.faces.push_back({a, b, c});
    attempt.face_owner.push_back(owner);
    attempt.owner_radius.push_back(radius);
    attempt.face_part.push_back(attempt.part_rings.size() - 1);
  };
  auto begin_part = [&](std::vector<std::size_t> rings, Attempt::Axis axis) {
    attempt.part_rings.push_back(std::move(rings));
    attempt.part_axis.push_back(axis);
  };
  for (const Join& join : joins) {
    begin_part(join.first_vertex, {});
    hull_faces(join.rings, join.first_vertex, join.points, join.optional, join.top, join.radius, hulls, add_face, attempt);
  }
  for (const Tube& tube : tubes) {
    const std::ptrdiff_t tube_id = static_cast<std::ptrdiff_t>(attempt.tube_parts.size());
    attempt.tube_parts.push_back({{tube.start_join, tube.end_join}, attempt.part_rings.size(), 0});
    const int sides = tube.rings.front().sides;
    const NodeId owner = tube.owner;
    const double radius = tube.rings.front().radius;
    std::vector<std::size_t> ids;
    if (tube.base) {
      ids.push_back(add_ring(vertices, tube.rings.front()));
      begin_part({ids[0]}, {tube.rings.front().centre, tube.base_centre, radius, tube_id});
      vertices.push_back(tube.base_centre);
      const std::size_t centre = vertices.size() - 1;
      for (int k = 0; k < sides; ++k) add_face(ids[0] + (k + 1) % sides, ids[0] + k, centre, owner, radius);
    } else {
      ids.push_back(tube.first_vertex);
    }
    for (std::size_t i = 1; i + 1 < tube.rings.size(); ++i) ids.push_back(add_ring(vertices, tube.rings[i]));
    ids.push_back(tube.tip ? add_ring(vertices, tube.rings.back()) : tube.last_vertex);
    for (std::size_t i = 0; i + 1 < ids.size(); ++i) {
      const std::size_t p = ids[i], q = ids[i + 1];
      // A band lies in the convex hull of its two rings: within the larger ring's radius of the
      // segment between their centres.
      begin_part({p, q}, {tube.rings[i].centre, tube.rings[i + 1].centre,
                          std::max(tube.rings[i].radius, tube.rings[i + 1].radius), tube_id});
      for (int k = 0; k < sides; ++k) {
        const std::size_t k1 = (k + 1) % sides;
        add_face(p + k, p + k1, q + k1, owner, radius);
        add_face(p + k, q + k1, q + k, owner, radius);
      }
    }
    if (tube.tip) {
      const Ring& last = tube.rings.back();
      vertices.push_back(last.centre + tube.apex_height * last.normal);
      const std::size_t apex = vertices.size() - 1, q = ids.back();
      begin_part({q}, {last.centre, vertices.back(), last.radius, tube_id});
      for (int k = 0; k < sides; ++k) add_face(q + k, q + (k + 1) % sides, apex, owner, radius);
    }
    attempt.tube_parts.back().end_part = attempt.part_rings.size();
  }
}

}  // namespace treeskel::modeling::detail
