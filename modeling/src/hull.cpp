#include "hull.h"

#include "treeskel/disjoint_sets.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Filtered_predicate.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <map>
#include <optional>
#include <stdexcept>
#include <utility>

namespace treeskel::modeling::detail {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Face = std::array<std::size_t, 3>;

/// CGAL's traits for the hull with its two tests that settle ties in exact binary floats (CGAL's
/// Mpzf) instead of GMP's rationals. A join's rings are flat, so the hull meets near-ties at almost
/// every face, and the rationals' allocations made half of its time. Both tests are signs of 3x3
/// determinants of differences, products only, so the answers are the same:
/// - which of two points lies farther from a plane through three points: the kernel's predicate
///   with the exact ring kernel for its fallback (as the kernel's own orientation test has it);
/// - which side of a face a point lies on: quickhull's filtered version of it is specialised for
///   CGAL's traits class alone and falls back on rationals; for another class it calls the kernel's
///   orientation test (static filter, intervals, then Mpzf).
struct HullTraits : CGAL::Convex_hull_traits_3<K, CGAL::Surface_mesh<K::Point_3>> {
  class Less_signed_distance_to_plane_3 {
   public:
    using result_type = bool;
    bool operator()(const Plane_3& h, const Point_3& p, const Point_3& q) const { return less_(h.p(), h.q(), h.r(), p, q); }

   private:
    CGAL::Filtered_predicate<K::Exact_kernel_rt::Less_signed_distance_to_plane_3, K::Approximate_kernel::Less_signed_distance_to_plane_3,
                             K::C2E_rt, K::C2F>
        less_;
  };
  Less_signed_distance_to_plane_3 less_signed_distance_to_plane_3_object() const { return {}; }
};

/// The boundary of `region` (faces of `faces`, by position) as one loop of point indices in the
/// faces' orientation, starting anywhere; nothing when the boundary is not a single loop or a
/// point of the region is not on it.
std::optional<std::vector<std::size_t>> boundary_loop(const std::vector<Face>& faces, const std::vector<std::size_t>& region) {
  std::map<std::pair<std::size_t, std::size_t>, int> edges;  // directed edge -> times met
  for (std::size_t f : region)
    for (int k = 0; k < 3; ++k) ++edges[{faces[f][k], faces[f][(k + 1) % 3]}];
  std::map<std::size_t, std::size_t> next;
  for (const auto& [e, count] : edges) {
    if (edges.count({e.second, e.first}) > 0) continue;  // inside the region
    if (count != 1 || !next.emplace(e.first, e.second).second) return std::nullopt;
  }
  if (next.size() < 3) return std::nullopt;
  std::vector<std::size_t> loop{next.begin()->first};
  while (loop.size() <= next.size()) {
    const auto it = next.find(loop.back());
    if (it == next.end()) return std::nullopt;
    if (it->second == loop.front()) break;
    loop.push_back(it->second);
  }
  if (loop.size() != next.size()) return std::nullopt;  // several loops, or one that runs on
  for (std::size_t f : region)
    for (std::size_t v : faces[f])
      if (next.count(v) == 0) return std::nullopt;  // a point inside the region
  return loop;
}

/// The fan over the convex polygon `loop` from its lowest point that makes no degenerate triangle;
/// nothing if none does.
std::optional<std::vector<Face>> canonical_fan(const std::vector<K::Point_3>& p, const std::vector<std::size_t>& loop) {
  const std::size_t m = loop.size();
  std::vector<std::size_t> order(m);
  for (std::size_t i = 0; i < m; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return loop[a] < loop[b]; });
  for (std::size_t apex : order) {
    std::vector<Face> fan;
    for (std::size_t i = 1; i + 1 < m; ++i) {
      const Face t{loop[apex], loop[(apex + i) % m], loop[(apex + i + 1) % m]};
      if (CGAL::collinear(p[t[0]], p[t[1]], p[t[2]])) break;
      fan.push_back(t);
    }
    if (fan.size() == m - 2) return fan;
  }
  return std::nullopt;
}

/// The convex polygon `loop` triangulated: cut along the lowest chord between two points of a
/// group that follow each other among the group's points on the loop but not on the loop itself
/// (an edge of the group's polygon), both sides triangulated so, and a polygon with no such chord
/// fanned (see canonical_fan). False, with `out` partly filled, if a fan did not fit.
bool triangulate(const std::vector<K::Point_3>& p, const std::vector<std::size_t>& group, const std::vector<std::size_t>& loop,
                 std::vector<Face>& out) {
  const std::size_t m = loop.size();
  std::map<std::size_t, std::vector<std::size_t>> members;  // group -> its positions on the loop, in order
  for (std::size_t i = 0; i < m; ++i) members[group[loop[i]]].push_back(i);
  std::optional<std::pair<std::size_t, std::size_t>> cut;  // positions, first < second
  std::pair<std::size_t, std::size_t> lowest;              // the cut's points, lower first
  for (const auto& [g, at] : members) {
    if (at.size() < 3) continue;
    for (std::size_t k = 0; k < at.size(); ++k) {
      const std::size_t i = at[k], j = at[(k + 1) % at.size()];
      if ((i + 1) % m == j || (j + 1) % m == i) continue;  // an edge of the loop
      const std::pair<std::size_t, std::size_t> ends{std::min(loop[i], loop[j]), std::max(loop[i], loop[j])};
      if (!cut || ends < lowest) {
        cut = std::pair<std::size_t, std::size_t>{std::min(i, j), std::max(i, j)};
        lowest = ends;
      }
    }
  }
  if (!cut) {
    const auto fan = canonical_fan(p, loop);
    if (!fan) return false;
    out.insert(out.end(), fan->begin(), fan->end());
    return true;
  }
  const auto [i, j] = *cut;
  const std::vector<std::size_t> inner(loop.begin() + static_cast<std::ptrdiff_t>(i), loop.begin() + static_cast<std::ptrdiff_t>(j) + 1);
  std::vector<std::size_t> outer(loop.begin() + static_cast<std::ptrdiff_t>(j), loop.end());
  outer.insert(outer.end(), loop.begin(), loop.begin() + static_cast<std::ptrdiff_t>(i) + 1);
  return triangulate(p, group, inner, out) && triangulate(p, group, outer, out);
}

}  // namespace

std::vector<Face> convex_hull_faces(const std::vector<Eigen::Vector3d>& points, const std::vector<std::size_t>& group_of) {
  std::vector<std::size_t> group = group_of;
  if (group.empty())
    for (std::size_t i = 0; i < points.size(); ++i) group.push_back(i);
  if (group.size() != points.size()) throw std::invalid_argument("convex_hull_faces: one group per point");
  std::vector<K::Point_3> p;
  p.reserve(points.size());
  // A corner of the hull -> its point's (last) index: (place, index) pairs sorted, one per place.
  using Place = std::array<double, 3>;
  std::vector<std::pair<Place, std::size_t>> index;
  index.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    p.emplace_back(points[i].x(), points[i].y(), points[i].z());
    index.push_back({{points[i].x(), points[i].y(), points[i].z()}, i});
  }
  std::sort(index.begin(), index.end());
  const auto index_of = [&](const K::Point_3& q) {
    const auto it = std::upper_bound(index.begin(), index.end(), Place{q.x(), q.y(), q.z()},
                                     [](const Place& a, const std::pair<Place, std::size_t>& b) { return a < b.first; });
    if (it == index.begin() || std::prev(it)->first != Place{q.x(), q.y(), q.z()}) throw std::logic_error("convex_hull_faces: a corner that is no point");
    return std::prev(it)->second;
  };
  CGAL::Surface_mesh<K::Point_3> hull;
  CGAL::convex_hull_3(p.begin(), p.end(), hull, HullTraits());
  std::vector<Face> faces;
  faces.reserve(hull.number_of_faces());
  for (auto f : hull.faces()) {
    Face corner{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(hull.halfedge(f), hull)) {
      if (k == 3) break;
      corner[static_cast<std::size_t>(k++)] = index_of(hull.point(v));
    }
    faces.push_back(corner);
  }
  // Neighbouring faces that lie in one plane form a region. Directed edge -> face, sorted.
  std::vector<std::pair<std::pair<std::size_t, std::size_t>, std::size_t>> face_of;
  face_of.reserve(3 * faces.size());
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (std::size_t k = 0; k < 3; ++k) face_of.push_back({{faces[f][k], faces[f][(k + 1) % 3]}, f});
  std::sort(face_of.begin(), face_of.end());
  DisjointSets<std::size_t> plane(faces.size());
  bool flat = false;
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const std::pair<std::size_t, std::size_t> back{faces[f][(k + 1) % 3], faces[f][k]};
      const auto twin = std::lower_bound(face_of.begin(), face_of.end(), back, [](const auto& e, const auto& key) { return e.first < key; });
      if (twin == face_of.end() || twin->first != back || twin->second < f) continue;
      const Face& g = faces[twin->second];
      const std::size_t opposite = g[0] + g[1] + g[2] - faces[f][k] - faces[f][(k + 1) % 3];
      if (CGAL::coplanar(p[faces[f][0]], p[faces[f][1]], p[faces[f][2]], p[opposite]) && plane.unite(f, twin->second)) flat = true;
    }
  if (!flat) return faces;
  std::map<std::size_t, std::vector<std::size_t>> regions;
  for (std::size_t f = 0; f < faces.size(); ++f) regions[plane.find(f)].push_back(f);
  std::vector<Face> out;
  for (const auto& [id, region] : regions) {
    std::vector<Face> again;
    const auto loop = region.size() > 1 ? boundary_loop(faces, region) : std::nullopt;
    if (loop && triangulate(p, group, *loop, again)) out.insert(out.end(), again.begin(), again.end());
    else
      for (std::size_t f : region) out.push_back(faces[f]);
  }
  return out;
}

}  // namespace treeskel::modeling::detail
