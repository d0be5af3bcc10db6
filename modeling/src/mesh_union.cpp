#include "mesh_union.h"

#include "face_tree.h"
#include "surface_mesh.h"

#include "treeskel/disjoint_sets.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/boost/graph/graph_traits_TriMesh_ArrayKernelT.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Random.h>
#include <CGAL/intersections.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/boost/graph/Face_filtered_graph.h>
#include <CGAL/boost/graph/copy_face_graph.h>
#include <CGAL/Surface_mesh.h>

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <optional>

namespace treeskel::modeling::detail {

namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
constexpr std::size_t kMaxGroup = 8;
constexpr std::size_t kMaxCorefinements = 48;
// Exact constructions: the points where two surfaces cross are kept exactly through every union (with
// rounded ones, a union can cross itself and the next one fail); they are rounded once at the end.
using K = CGAL::Exact_predicates_exact_constructions_kernel;
using Surface = CGAL::Surface_mesh<K::Point_3>;

void append(Surface& out, const TreeMesh& mesh) { append_to_surface(out, mesh); }

/// A point as doubles that do not depend on what was computed before: a lazy number's interval
/// narrows once something needed its exact value (and what did depends on the order corefinement
/// met the faces in, which follows their addresses), so its midpoint is not stable. The interval of
/// a coordinate the inputs held is a single double; a point with another is taken exactly. (From the
/// point's own interval and exact value: its coordinates as lazy numbers were an allocation each, a
/// third of the time of this conversion on the LPine1 plot's tree 11.)
std::array<double, 3> coordinates(const K::Point_3& p) {
  const auto& a = p.approx();
  if (a.x().inf() == a.x().sup() && a.y().inf() == a.y().sup() && a.z().inf() == a.z().sup())
    return {a.x().inf(), a.y().inf(), a.z().inf()};
  const auto& e = p.exact();
  return {CGAL::to_double(e.x()), CGAL::to_double(e.y()), CGAL::to_double(e.z())};
}

/// Removes the surfaces of the voids a union encloses, and returns how many. Pieces that cross one
/// another and the tree can close a pocket of air between them (seed 4's tree5_missing_3 enclosed a
/// tetrahedron 0.1 mm across): the union's boundary then holds a component of its own that faces
/// inward, which every check counts as a second component. Wood has no voids: each component but
/// the largest whose volume, summed exactly, is negative is removed, which fills its void.
std::size_t fill_voids(Surface& s) {
  auto component = s.add_property_map<Surface::Face_index, std::size_t>("f:treeskel_component", 0).first;
  const std::size_t n = PMP::connected_components(s, component);
  std::vector<std::size_t> voids;
  if (n > 1) {
    std::vector<std::size_t> faces(n, 0);
    for (auto f : s.faces()) ++faces[component[f]];
    const auto largest = static_cast<std::size_t>(std::max_element(faces.begin(), faces.end()) - faces.begin());
    // Six times each component's signed volume, from its own first point (small numbers).
    std::vector<K::FT> volume(n, K::FT(0));
    std::vector<std::optional<K::Point_3>> origin(n);
    for (auto f : s.faces()) {
      const std::size_t c = component[f];
      if (c == largest) continue;
      const auto h = s.halfedge(f);
      const K::Point_3& p = s.point(s.source(h));
      if (!origin[c]) origin[c] = p;
      const K::Point_3& o = *origin[c];
      volume[c] += CGAL::determinant(p - o, s.point(s.target(h)) - o, s.point(s.target(s.next(h))) - o);
    }
    for (std::size_t c = 0; c < n; ++c)
      if (c != largest && CGAL::is_negative(volume[c])) voids.push_back(c);
    if (!voids.empty()) {
      PMP::remove_connected_components(s, voids, component);
      s.collect_garbage();
    }
  }
  s.remove_property_map(component);
  return voids.size();
}

/// The mesh with its points rounded to 32-bit floats in the frame `offset` leads to, in a canonical
/// order (vertices by position, faces by their vertices): corefinement's own order differs from run
/// to run, the result must not.
TreeMesh to_tree_mesh(const Surface& s, const Eigen::Vector3d& offset) {
  std::vector<std::array<double, 3>> points;
  std::vector<Surface::Vertex_index> ids;
  std::vector<std::size_t> index_of(s.number_of_vertices() + s.number_of_removed_vertices());
  for (auto v : s.vertices()) {
    // A coordinate's float from the ends of its lazy number's interval where both round to it (the
    // rounding is monotone, so the exact value between them does too, however narrow the interval
    // is this time), else from the exact value: the exact values of the points the unions made were
    // most of this conversion's time (18 of 33 ms on bench_model's 10k-node mesh).
    const auto& a = s.point(v).approx();
    std::array<double, 3> q;
    bool settled = true;
    for (int k = 0; k < 3 && settled; ++k) {
      const double low = file_float(a[k].inf(), offset[k]), high = file_float(a[k].sup(), offset[k]);
      settled = low == high;
      q[static_cast<std::size_t>(k)] = low - offset[k];
    }
    if (!settled) {
      const std::array<double, 3> exact = coordinates(s.point(v));
      for (int k = 0; k < 3; ++k) q[static_cast<std::size_t>(k)] = file_float(exact[static_cast<std::size_t>(k)], offset[k]) - offset[k];
    }
    index_of[v] = ids.size();
    points.push_back(q);
    ids.push_back(v);
  }
  // Their doubles break ties between points that round to one float (only those: the order compares
  // them nowhere else).
  std::vector<std::array<double, 3>> unrounded(points.size());
  {
    std::vector<std::size_t> by_point(points.size());
    std::iota(by_point.begin(), by_point.end(), std::size_t{0});
    std::sort(by_point.begin(), by_point.end(), [&](std::size_t x, std::size_t y) { return points[x] < points[y]; });
    for (std::size_t k = 0; k < by_point.size(); ++k) {
      const bool tied = (k > 0 && points[by_point[k - 1]] == points[by_point[k]]) ||
                        (k + 1 < by_point.size() && points[by_point[k + 1]] == points[by_point[k]]);
      if (tied) unrounded[by_point[k]] = coordinates(s.point(ids[by_point[k]]));
    }
  }
  const auto exact_less = [&](std::size_t a, std::size_t b) {
    return CGAL::compare_xyz(s.point(ids[a]), s.point(ids[b])) == CGAL::SMALLER;
  };
  const auto neighbours = [&](std::size_t i) {
    std::vector<std::size_t> out;
    if (s.halfedge(ids[i]) == Surface::null_halfedge()) return out;  // a vertex no face uses
    for (auto h : CGAL::halfedges_around_target(s.halfedge(ids[i]), s)) out.push_back(index_of[s.source(h)]);
    return out;
  };
  const std::vector<std::size_t> order = canonical_vertex_order(points, unrounded, exact_less, neighbours);
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
  std::vector<std::array<double, 3>> sorted;
  for (std::size_t k : order) sorted.push_back(points[k]);
  split_pinched_vertices(sorted, faces);
  TreeMesh out;
  out.reserve(sorted.size(), 3 * faces.size() / 2, faces.size());
  std::vector<TreeMesh::VertexHandle> handle;
  handle.reserve(sorted.size());
  for (const auto& p : sorted) handle.push_back(out.add_vertex(TreeMesh::Point(p[0], p[1], p[2])));
  for (const auto& c : faces) out.add_face(handle[c[0]], handle[c[1]], handle[c[2]]);
  return out;
}

/// Which side of a closed mesh a point lies on (an AABB tree of its faces in doubles, exact predicates).
/// A mesh without faces holds no point (CGAL's test would read the root of an empty tree: a tree
/// whose own sweep left every branch apart crashed its union so).
class SideOf {
 public:
  explicit SideOf(const TreeMesh& mesh) : tree_(faces(mesh).first, faces(mesh).second, mesh) {}
  CGAL::Bounded_side operator()(const GT::Point_3& p) const {
    return tree_.empty() ? CGAL::ON_UNBOUNDED_SIDE : SideOfFaces(tree_)(p);
  }

 private:
  FaceTree tree_;
};

}  // namespace

struct MeshDepth::Tree {
  explicit Tree(const TreeMesh& mesh) : aabb(faces(mesh).first, faces(mesh).second, mesh) { aabb.accelerate_distance_queries(); }
  FaceTree aabb;
};

MeshDepth::MeshDepth(const TreeMesh& mesh) : tree_(std::make_unique<Tree>(mesh)) {}
MeshDepth::~MeshDepth() = default;

double MeshDepth::operator()(const Eigen::Vector3d& p) const {
  if (tree_->aabb.empty()) return -std::numeric_limits<double>::infinity();
  const GT::Point_3 q(p.x(), p.y(), p.z());
  const double d = std::sqrt(CGAL::to_double(tree_->aabb.squared_distance(q)));
  const auto side = SideOfFaces(tree_->aabb)(q);
  return side == CGAL::ON_BOUNDED_SIDE ? d : -d;
}

Eigen::Vector3d MeshDepth::nearest(const Eigen::Vector3d& p) const {
  if (tree_->aabb.empty()) return p;
  const auto q = tree_->aabb.closest_point(GT::Point_3(p.x(), p.y(), p.z()));
  return {CGAL::to_double(q.x()), CGAL::to_double(q.y()), CGAL::to_double(q.z())};
}

namespace {

/// Whether `meet` holds for some box of `a` and box of `b` that overlap (the box intersection stops
/// at the first such pair). Reorders both.
template <class Box, class Meet>
bool some_pair_meets(std::vector<Box>& a, std::vector<Box>& b, Meet meet) {
  if (a.empty() || b.empty()) return false;
  struct Met {};
  try {
    CGAL::box_intersection_d(a.begin(), a.end(), b.begin(), b.end(), [&](const Box& p, const Box& q) {
      if (meet(p, q)) throw Met{};
    });
  } catch (const Met&) {
    return true;
  }
  return false;
}

/// Whether two closed pieces cross or one holds the other, as `PMP::do_intersect` with the overlap
/// test of bounded sides decides it, but with each piece's triangles, AABB tree and points made once,
/// not for every pair tested (on a crowded pine of the LPine1 plot those trees were 8% of its model),
/// and only the faces inside the other piece's box tested.
class Overlaps {
 public:
  explicit Overlaps(const std::vector<TreeMesh>& pieces)
      : pieces_(pieces), trees_(pieces.size()), points_(pieces.size()), faces_(pieces.size()) {}

  bool operator()(std::size_t i, std::size_t j) { return surfaces_meet(i, j) || holds(i, j) || holds(j, i); }

  /// Where `p` lies with respect to piece `i`.
  CGAL::Bounded_side side(std::size_t i, const GT::Point_3& p) {
    if (!trees_[i]) trees_[i] = std::make_unique<SideOf>(pieces_[i]);
    return (*trees_[i])(p);
  }

 private:
  /// Whether piece `a` holds piece `b`, their surfaces apart: then every component of `b` lies
  /// wholly inside or wholly outside `a`, and any one of its points tells which.
  bool holds(std::size_t a, std::size_t b) {
    if (points_[b].empty()) points_[b] = one_point_per_component(pieces_[b]);
    return std::any_of(points_[b].begin(), points_[b].end(), [&](const GT::Point_3& p) { return side(a, p) == CGAL::ON_BOUNDED_SIDE; });
  }

  /// A piece's triangles and their boxes, by face index, and the box of them all.
  struct Faces {
    std::vector<GT::Triangle_3> triangle;
    std::vector<CGAL::Bbox_3> box;
    CGAL::Bbox_3 all;
  };

  const Faces& faces(std::size_t i) {
    Faces& out = faces_[i];
    if (!out.triangle.empty() || pieces_[i].n_faces() == 0) return out;
    const TreeMesh& mesh = pieces_[i];
    out.triangle.reserve(mesh.n_faces());
    out.box.reserve(mesh.n_faces());
    for (auto f : mesh.faces()) {
      std::array<GT::Point_3, 3> p;
      std::size_t k = 0;
      for (auto v : mesh.fv_range(f)) {
        const auto& q = mesh.point(v);
        p[k++] = GT::Point_3(q[0], q[1], q[2]);
      }
      out.triangle.emplace_back(p[0], p[1], p[2]);
      out.box.push_back(out.triangle.back().bbox());
      out.all += out.box.back();
    }
    return out;
  }

  /// Whether a face of piece `i` and one of piece `j` have a point in common (CGAL's triangle test,
  /// as `PMP::do_intersect` makes it): of each, only the faces whose boxes meet the other's box go to
  /// the box intersection. (`PMP::do_intersect` sorted the boxes of both whole pieces for every pair:
  /// with `--complete-all` a limb's thousands of faces for each twig beside it, 4.7 of the 10.9 s
  /// of AdTree's Lille_2's unions.)
  bool surfaces_meet(std::size_t i, std::size_t j) {
    using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;
    const Faces& a = faces(i);
    const Faces& b = faces(j);
    if (a.triangle.empty() || b.triangle.empty() || !CGAL::do_overlap(a.all, b.all)) return false;
    auto near = [](const Faces& mine, const CGAL::Bbox_3& theirs) {
      std::vector<Box> out;
      for (std::size_t f = 0; f < mine.box.size(); ++f)
        if (CGAL::do_overlap(mine.box[f], theirs)) out.emplace_back(mine.box[f], f);
      return out;
    };
    std::vector<Box> x = near(a, b.all), y = near(b, a.all);
    return some_pair_meets(x, y, [&](const Box& p, const Box& q) {
      return CGAL::do_intersect(a.triangle[p.info()], b.triangle[q.info()]);
    });
  }

  static std::vector<GT::Point_3> one_point_per_component(const TreeMesh& mesh) {
    DisjointSets<std::size_t> parts(mesh.n_vertices());
    for (auto f : mesh.faces()) {
      auto h = mesh.halfedge_handle(f);
      const auto first = static_cast<std::size_t>(mesh.to_vertex_handle(h).idx());
      for (int corner = 1; corner < 3; ++corner) {
        h = mesh.next_halfedge_handle(h);
        parts.unite(first, static_cast<std::size_t>(mesh.to_vertex_handle(h).idx()));
      }
    }
    std::vector<GT::Point_3> out;
    std::vector<char> seen(mesh.n_vertices(), 0);
    for (auto f : mesh.faces()) {
      const auto v = mesh.to_vertex_handle(mesh.halfedge_handle(f));
      auto& s = seen[parts.find(static_cast<std::size_t>(v.idx()))];
      if (s) continue;
      s = 1;
      const auto& p = mesh.point(v);
      out.emplace_back(p[0], p[1], p[2]);
    }
    return out;
  }

  const std::vector<TreeMesh>& pieces_;
  std::vector<std::unique_ptr<SideOf>> trees_;
  std::vector<std::vector<GT::Point_3>> points_;
  std::vector<Faces> faces_;
};

/// Corefines `piece` into `whole` (their union replaces `whole`); false, with `whole` unchanged, if
/// CGAL refuses.
bool unite_into(Surface& whole, Surface piece) {
  bool ok = false;
  Surface copy = whole;  // the union is made in the copy, in place: `whole` stays if CGAL refuses
  try {
    ok = PMP::corefine_and_compute_union(copy, piece, copy);
  } catch (const std::exception&) {
    ok = false;
  }
  if (ok) whole = std::move(copy);
  return ok;
}

/// The whole tree as pieces are united into it. A connected part of a piece whose surface meets none
/// of the whole's is not given to corefinement: it lies inside the whole (and is dropped, as the
/// union would drop it) or outside (and is joined as it is, as the union would keep it). To tell
/// which, corefinement builds an AABB tree of the whole in exact numbers: on AdTree's Lille_2 that
/// was most of the 1.15 s its one union of 80k faces of pieces with the 240k-face tree took.
class Whole {
 public:
  Whole(const TreeMesh& base, const std::vector<Eigen::AlignedBox3d>& boxes, Overlaps& sides)
      : base_(base), boxes_(boxes), sides_(sides) {
    append(surface_, base);
  }

  Surface& surface() { return surface_; }

  /// Unites `piece`, the union of the pieces `members`, into the whole; false, with the whole
  /// unchanged, if CGAL refuses. `corefinements` counts the corefinements run. Each part is decided
  /// on its own, as corefinement decides a part its intersections leave whole.
  bool unite(Surface piece, const std::vector<std::size_t>& members, std::size_t& corefinements) {
    auto part = piece.add_property_map<Surface::Face_index, std::size_t>("f:part").first;
    const std::size_t parts = PMP::connected_components(piece, part);
    const std::vector<CGAL::Bbox_3> face_box = face_boxes(piece);
    std::vector<CGAL::Bbox_3> part_box(parts);
    for (auto f : piece.faces()) part_box[part[f]] += face_box[f];
    // 1: corefined with the whole; 0: inside it, dropped; 2: outside it, joined as it is.
    std::vector<int> fate(parts, 1);
    const std::vector<char> meets = parts_meeting(piece, part, face_box, part_box);
    for (std::size_t c = 0; c < parts; ++c) {
      if (meets[c]) continue;
      const auto p = input_point(piece, part, c);
      const auto in = p ? inside(*p) : std::nullopt;
      if (in) fate[c] = *in ? 0 : 2;
    }
    bool ok = true;
    if (std::all_of(fate.begin(), fate.end(), [](int f) { return f == 1; })) {
      ++corefinements;
      ok = unite_into(surface_, std::move(piece));
    } else {
      Surface rest = parts_of(piece, part, fate, 1), outside = parts_of(piece, part, fate, 2);
      if (!rest.is_empty()) {
        ++corefinements;
        ok = unite_into(surface_, std::move(rest));
      }
      if (ok) surface_.join(outside);
    }
    if (ok) united_.insert(united_.end(), members.begin(), members.end());
    return ok;
  }

 private:
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, Surface::Face_index>;

  /// The boxes of the faces of `s`, by face index (each vertex's box taken once).
  static std::vector<CGAL::Bbox_3> face_boxes(const Surface& s) {
    std::vector<CGAL::Bbox_3> at(s.number_of_vertices() + s.number_of_removed_vertices());
    for (auto v : s.vertices()) at[v] = s.point(v).bbox();
    std::vector<CGAL::Bbox_3> out(s.number_of_faces() + s.number_of_removed_faces());
    for (auto f : s.faces()) {
      const auto h = s.halfedge(f);
      out[f] = at[s.target(h)] + at[s.target(s.next(h))] + at[s.source(h)];
    }
    return out;
  }

  static bool within(const CGAL::Bbox_3& in, const CGAL::Bbox_3& box) {
    return box.xmin() <= in.xmin() && in.xmax() <= box.xmax() && box.ymin() <= in.ymin() && in.ymax() <= box.ymax() &&
           box.zmin() <= in.zmin() && in.zmax() <= box.zmax();
  }

  static K::Triangle_3 triangle(const Surface& s, Surface::Face_index f) {
    const auto h = s.halfedge(f);
    return {s.point(s.target(h)), s.point(s.target(s.next(h))), s.point(s.source(h))};
  }

  /// Which parts of `piece` have a point in common with the whole's surface (exact tests of the
  /// face pairs whose boxes meet), or might hold a component of it: the box of one of the whole's
  /// components lies in theirs. (The union would drop that component; corefinement is left to find
  /// out.)
  std::vector<char> parts_meeting(const Surface& piece, const Surface::Property_map<Surface::Face_index, std::size_t>& part,
                                  const std::vector<CGAL::Bbox_3>& face_box, const std::vector<CGAL::Bbox_3>& part_box) {
    const std::size_t parts = part_box.size();
    std::vector<char> meets(parts, 0);
    CGAL::Bbox_3 bound;
    for (const auto& b : part_box) bound += b;
    const std::vector<CGAL::Bbox_3> box = face_boxes(surface_);
    std::vector<Box> theirs;
    {
      std::size_t count = 0;
      for (auto f : surface_.faces()) count += CGAL::do_overlap(box[f], bound) ? 1 : 0;
      theirs.reserve(count);
      for (auto f : surface_.faces())
        if (CGAL::do_overlap(box[f], bound)) theirs.emplace_back(box[f], f);
    }
    std::vector<std::vector<Box>> mine(parts);
    {
      std::vector<std::size_t> count(parts, 0);
      for (auto f : piece.faces()) ++count[part[f]];
      for (std::size_t c = 0; c < parts; ++c) mine[c].reserve(count[c]);
      for (auto f : piece.faces()) mine[part[f]].emplace_back(face_box[f], f);
    }
    std::vector<Box> near;
    for (std::size_t c = 0; c < parts; ++c) {
      if (meets[c]) continue;
      near.clear();
      for (const auto& b : theirs)
        if (CGAL::do_overlap(b.bbox(), part_box[c])) near.push_back(b);
      meets[c] = some_pair_meets(mine[c], near, [&](const Box& a, const Box& b) {
        return faces_meet(piece, a.info(), surface_, b.info());
      }) ? 1 : 0;
    }
    if (std::find(meets.begin(), meets.end(), 0) != meets.end()) {
      // The whole's components, found only when some part meets none of its faces (seldom).
      auto component = surface_.add_property_map<Surface::Face_index, std::size_t>("f:component").first;
      std::vector<CGAL::Bbox_3> component_box(PMP::connected_components(surface_, component));
      for (auto f : surface_.faces()) component_box[component[f]] += box[f];
      surface_.remove_property_map(component);
      for (std::size_t c = 0; c < parts; ++c)
        for (const auto& b : component_box)
          if (!meets[c] && within(b, part_box[c])) meets[c] = 1;
    }
    return meets;
  }

  /// Whether two faces have a point in common: in doubles (exact predicates) when their points are
  /// doubles, as the inputs' are, else in exact numbers.
  static bool faces_meet(const Surface& s, Surface::Face_index f, const Surface& t, Surface::Face_index g) {
    std::array<GT::Point_3, 6> p;
    std::size_t k = 0;
    for (const auto& [m, face] : {std::pair{&s, f}, std::pair{&t, g}})
      for (auto v : CGAL::vertices_around_face(m->halfedge(face), *m)) {
        const auto q = as_double(m->point(v));
        if (!q) return CGAL::do_intersect(triangle(s, f), triangle(t, g));
        p[k++] = *q;
      }
    return CGAL::do_intersect(GT::Triangle_3(p[0], p[1], p[2]), GT::Triangle_3(p[3], p[4], p[5]));
  }

  /// The point as doubles if its coordinates are doubles (as the inputs' are, not the ones unions make).
  static std::optional<GT::Point_3> as_double(const K::Point_3& p) {
    const auto x = CGAL::to_interval(p.x()), y = CGAL::to_interval(p.y()), z = CGAL::to_interval(p.z());
    if (x.first != x.second || y.first != y.second || z.first != z.second) return std::nullopt;
    return GT::Point_3(x.first, y.first, z.first);
  }

  /// A vertex of part `c` whose coordinates are doubles (one of the input's, not one a union made).
  static std::optional<GT::Point_3> input_point(const Surface& piece, const Surface::Property_map<Surface::Face_index, std::size_t>& part,
                                               std::size_t c) {
    for (auto f : piece.faces()) {
      if (part[f] != c) continue;
      for (auto v : CGAL::vertices_around_face(piece.halfedge(f), piece))
        if (const auto p = as_double(piece.point(v))) return p;
    }
    return std::nullopt;
  }

  /// Whether `p`, on none of the whole's surface, lies inside the whole: the base and the pieces
  /// united so far, as closed meshes of doubles; empty if `p` lies on one of their surfaces (inside
  /// another: the whole's surface is not theirs there).
  std::optional<bool> inside(const GT::Point_3& p) {
    if (!base_side_) base_side_ = std::make_unique<SideOf>(base_);
    bool in = false;
    auto add = [&](CGAL::Bounded_side side) {
      if (side == CGAL::ON_BOUNDARY) return false;
      in = in || side == CGAL::ON_BOUNDED_SIDE;
      return true;
    };
    if (!add((*base_side_)(p))) return std::nullopt;
    const Eigen::Vector3d q(p.x(), p.y(), p.z());
    for (std::size_t i : united_)
      if (boxes_[i].contains(q) && !add(sides_.side(i, p))) return std::nullopt;
    return in;
  }

  /// The faces of `piece` whose part's fate is `which`, as a mesh of their own.
  static Surface parts_of(const Surface& piece, const Surface::Property_map<Surface::Face_index, std::size_t>& part,
                          const std::vector<int>& fate, int which) {
    std::vector<std::size_t> chosen;
    for (std::size_t c = 0; c < fate.size(); ++c)
      if (fate[c] == which) chosen.push_back(c);
    Surface out;
    if (chosen.empty()) return out;
    CGAL::copy_face_graph(CGAL::Face_filtered_graph<Surface>(piece, chosen, part), out);
    return out;
  }

  const TreeMesh& base_;
  const std::vector<Eigen::AlignedBox3d>& boxes_;
  Overlaps& sides_;
  Surface surface_;
  std::unique_ptr<SideOf> base_side_;
  std::vector<std::size_t> united_;  // the pieces in the whole
};

}  // namespace

struct GroupUnions::Store {
  struct Made {
    Surface surface;
    std::vector<std::size_t> taken;  // the positions among the group's pieces united into it, the first first
    std::vector<std::size_t> left;   // the positions it did not take
    std::size_t attempts = 0;        // unions tried
  };
  /// By the group's pieces: each one's points and then its faces' vertex indices, in order.
  std::map<std::vector<std::vector<double>>, Made> made;
};

GroupUnions::GroupUnions() : store_(std::make_unique<Store>()) {}
GroupUnions::~GroupUnions() = default;

namespace {

/// A mesh as its points and then its faces' vertex indices: equal for equal meshes.
std::vector<double> shape_of(const TreeMesh& mesh) {
  std::vector<double> out;
  out.reserve(3 * mesh.n_vertices() + 3 * mesh.n_faces());
  for (auto v : mesh.vertices())
    for (int k = 0; k < 3; ++k) out.push_back(mesh.point(v)[k]);
  for (auto f : mesh.faces())
    for (auto v : mesh.fv_range(f)) out.push_back(static_cast<double>(v.idx()));
  return out;
}

}  // namespace

void split_pinched_vertices(std::vector<std::array<double, 3>>& points, std::vector<std::array<std::size_t, 3>>& faces) {
  // The faces around each vertex, in face order (a CSR list: one allocation, not one per vertex).
  const std::size_t n = points.size();
  std::vector<std::size_t> first(n + 1, 0), around(3 * faces.size());
  for (const auto& f : faces)
    for (std::size_t v : f) ++first[v + 1];
  std::partial_sum(first.begin(), first.end(), first.begin());
  {
    std::vector<std::size_t> at(first.begin(), first.end() - 1);
    for (std::size_t f = 0; f < faces.size(); ++f)
      for (std::size_t v : faces[f]) around[at[v]++] = f;
  }
  std::vector<std::pair<std::size_t, std::size_t>> ends;  // (other end of an edge from v, face i)
  std::vector<std::size_t> copy;                          // per fan (by its representative): its vertex
  for (std::size_t v = 0; v < n; ++v) {
    const std::size_t* fs = around.data() + first[v];
    const std::size_t k = first[v + 1] - first[v];
    if (k < 2) continue;
    // Faces around v that share an edge from v are in one fan.
    ends.clear();
    for (std::size_t i = 0; i < k; ++i)
      for (std::size_t w : faces[fs[i]])
        if (w != v) ends.emplace_back(w, i);
    std::sort(ends.begin(), ends.end());
    DisjointSets<std::size_t> fan(k);
    std::size_t fans = k;
    for (std::size_t e = 1; e < ends.size(); ++e)
      if (ends[e].first == ends[e - 1].first && fan.unite(ends[e - 1].second, ends[e].second)) --fans;
    if (fans == 1) continue;  // one fan: a manifold vertex, as nearly all are
    // The fan of the first face keeps v; each other fan, in the order of its first face, a copy.
    constexpr auto kUnset = std::numeric_limits<std::size_t>::max();
    copy.assign(k, kUnset);
    for (std::size_t i = 0; i < k; ++i) {
      std::size_t& to = copy[fan.find(i)];
      if (to == kUnset) {  // the first face of a fan (face 0 starts the first)
        to = i == 0 ? v : points.size();
        if (i != 0) points.push_back(points[v]);
      }
      for (auto& c : faces[fs[i]])
        if (c == v) c = to;
    }
  }
}

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

/// The half of edge `e` whose collapse (its start onto its end) keeps the mesh manifold and turns no
/// face over, or an invalid handle.
TreeMesh::HalfedgeHandle collapsible(TreeMesh& mesh, TreeMesh::EdgeHandle e, double weld) {
  for (int side = 0; side < 2; ++side) {
    const auto h = mesh.halfedge_handle(e, side);
    if (!mesh.is_collapse_ok(h)) continue;
    const auto from = mesh.from_vertex_handle(h), to = mesh.to_vertex_handle(h);
    if (turns_a_face(mesh, from, to, mesh.point(to), weld)) continue;
    return h;
  }
  return {};
}

/// Collapses edge `e` onto one of its ends if that keeps the mesh manifold and turns no face over.
bool collapse_edge(TreeMesh& mesh, TreeMesh::EdgeHandle e, double weld) {
  const auto h = collapsible(mesh, e, weld);
  if (!h.is_valid()) return false;
  mesh.collapse(h);
  return true;
}

}  // namespace

Eigen::AlignedBox3d bounding_box(const TreeMesh& mesh) {
  Eigen::AlignedBox3d box;
  for (auto v : mesh.vertices()) {
    const auto p = mesh.point(v);
    box.extend(Eigen::Vector3d(p[0], p[1], p[2]));
  }
  return box;
}

std::vector<std::size_t> faces_around(const TreeMesh& mesh, const std::vector<std::size_t>& faces) {
  std::vector<std::size_t> out(faces);
  for (std::size_t f : faces)
    for (auto v : mesh.fv_range(mesh.face_handle(static_cast<unsigned>(f))))
      for (auto g : mesh.vf_range(v)) out.push_back(static_cast<std::size_t>(g.idx()));
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::size_t collapse_shortest_edges(TreeMesh& mesh, const std::vector<std::size_t>& faces, double max_length,
                                   double sliver, std::vector<Eigen::AlignedBox3d>* moved) {
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_face_status();
  std::size_t done = 0;
  for (std::size_t f : faces) {
    const auto fh = mesh.face_handle(static_cast<unsigned>(f));
    if (!fh.is_valid() || mesh.status(fh).deleted()) continue;
    // Its edges no longer than `max_length`, shortest first (of two as long, the later one): where
    // the shortest may not go (its collapse would pinch the mesh or turn a face over), the next may.
    std::array<std::pair<double, TreeMesh::EdgeHandle>, 3> edges;
    std::size_t count = 0;
    for (auto h : mesh.fh_range(fh)) {
      const double l = mesh.calc_edge_sqr_length(mesh.edge_handle(h));
      if (l <= max_length * max_length) edges[count++] = {l, mesh.edge_handle(h)};
    }
    std::reverse(edges.begin(), edges.begin() + static_cast<std::ptrdiff_t>(count));
    std::stable_sort(edges.begin(), edges.begin() + static_cast<std::ptrdiff_t>(count),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    TreeMesh::HalfedgeHandle h;
    for (std::size_t k = 0; k < count && !h.is_valid(); ++k) h = collapsible(mesh, edges[k].second, sliver);
    if (!h.is_valid()) continue;
    // The faces a collapse changes are those around the end that goes, which then hold the other
    // end: the box of the vertices around both ends holds them as they were and as they become.
    if (moved) {
      Eigen::AlignedBox3d around;
      for (const auto end : {mesh.from_vertex_handle(h), mesh.to_vertex_handle(h)})
        for (auto v : mesh.vv_range(end)) {
          const auto p = mesh.point(v);
          around.extend(Eigen::Vector3d(p[0], p[1], p[2]));
        }
      moved->push_back(around);
    }
    mesh.collapse(h);
    ++done;
  }
  if (done > 0) mesh.garbage_collection();  // nothing deleted: the handles stand, and a pass costs a copy
  return done;
}

std::size_t weld_short_edges(TreeMesh& mesh, double weld, const std::vector<Eigen::AlignedBox3d>& where) {
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_face_status();
  std::size_t welded = 0;
  const double weld2 = weld * weld;
  for (bool again = true; again;) {
    again = false;
    for (auto e : mesh.edges()) {
      if (mesh.status(e).deleted() || mesh.calc_edge_sqr_length(e) > weld2) continue;
      if (!where.empty()) {
        const auto p = mesh.point(mesh.from_vertex_handle(mesh.halfedge_handle(e, 0)));
        const Eigen::Vector3d q(p[0], p[1], p[2]);
        if (std::none_of(where.begin(), where.end(), [&](const Eigen::AlignedBox3d& b) { return b.contains(q); })) continue;
      }
      // Onto the end that stays (vertices keep their rounded coordinates).
      const bool done = collapse_edge(mesh, e, weld);
      if (!done) continue;
      ++welded;
      again = true;
    }
  }
  if (welded > 0) mesh.garbage_collection();
  return welded;
}

UnionResult unite(const TreeMesh& base, const std::vector<TreeMesh>& pieces, double weld, const Eigen::Vector3d& offset,
                  const std::vector<Eigen::AlignedBox3d>& where, bool pieces_tested, GroupUnions* made) {
  // Nothing here is known to draw from CGAL's default random generator (box intersection and the
  // side-of-mesh test use generators of their own, seeded the same every time); it is seeded anyway,
  // so that a CGAL version whose corefinement did would still give the same mesh for the same input.
  CGAL::get_default_random() = CGAL::Random(0);
  UnionResult out;
  std::vector<Eigen::AlignedBox3d> boxes;
  for (const auto& p : pieces) {
    Eigen::AlignedBox3d b = bounding_box(p);
    const double grow = 1e-6 * std::max(b.sizes().maxCoeff(), 1e-300);
    b.min().array() -= grow;
    b.max().array() += grow;
    boxes.push_back(b);
  }
  // A piece the union refuses is kept beside the mesh: its triangles are returned as they are, apart
  // from the united mesh. (Joined into the whole, a piece that is open, crosses itself or crosses
  // the whole, which is why it was refused, broke corefinement's precondition for every union after
  // it, in this call or the caller's next: CGAL crashed on completed models of AdTree's Lille_11.)
  Surface apart;
  auto keep_apart = [&](const Surface& s, std::size_t count) {
    apart.join(s);
    out.failed += count;
  };
  std::vector<Surface> surfaces(pieces.size());
  std::vector<std::size_t> usable;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    // Corefinement needs closed inputs free of self-intersections (CGAL may crash otherwise). The
    // tests run on the pieces' own doubles (exact predicates decide them as the exact kernel would).
    append(surfaces[i], pieces[i]);
    if (!CGAL::is_closed(pieces[i]) || (!pieces_tested && PMP::does_self_intersect(pieces[i]))) keep_apart(surfaces[i], 1);
    else usable.push_back(i);
  }
  // A corefinement with the whole costs as much as the whole is large: the pieces that cross or hold
  // one another are united among themselves first, and the groups, which neither cross nor hold one
  // another, go into one corefinement with the whole. (Uniting every two pieces whose boxes overlap,
  // without testing them exactly, cost twice as much on AdTree's tree1: the unions are not cheap.)
  Overlaps overlap(pieces);
  Whole whole(base, boxes, overlap);
  struct Group {
    Surface surface;
    std::vector<std::size_t> members;  // the pieces united into it
  };
  std::vector<std::size_t> alone;  // pieces their group's union refused, united with the whole alone
  // A budget: points made by one union and cut again by the next hold ever longer exact numbers,
  // and a leafy crown whose twigs all cross one another made a group's unions run for minutes. A
  // group takes at most kMaxGroup pieces (the others are united with the whole alone), and past
  // kMaxCorefinements, or one corefinement a piece where there are more pieces, the pieces left are
  // skipped (the caller leaves them out and says so). (A flat 48 left out 67 of the 138 limbs of
  // tree 10 of the LPine1 plot, 63% of its skeleton, once a model pruned less: it needs 57.)
  std::size_t budget = std::max(kMaxCorefinements, usable.size());
  auto try_unite = [&](Surface& into, Surface piece) {
    if (budget == 0) return false;
    --budget;
    ++out.batches;
    return unite_into(into, std::move(piece));
  };
  auto try_unite_whole = [&](Surface piece, const std::vector<std::size_t>& members) {
    if (budget == 0) return false;
    --budget;
    return whole.unite(std::move(piece), members, out.batches);
  };
  // In rounds: the pieces a full group left over make groups of their own in the next round, again
  // one corefinement with the whole, as long as each round leaves fewer. (Left to the layers below,
  // the three that AdTree's tree1 left over took two corefinements of its 72k-face mesh, and Lille_11
  // two of 140k faces.)
  std::vector<std::size_t> round = usable;
  for (bool again = true; again;) {
    // The pieces that cross or hold one another are linked.
    DisjointSets<std::size_t> linked(pieces.size());
    for (std::size_t a = 0; a < round.size(); ++a)
      for (std::size_t b = a + 1; b < round.size(); ++b) {
        const std::size_t i = round[a], j = round[b];
        if (linked.find(i) != linked.find(j) && boxes[i].intersects(boxes[j]) && overlap(i, j)) linked.unite(i, j);
      }
    std::vector<Group> groups;
    std::vector<std::ptrdiff_t> group_of(pieces.size(), -1);
    std::vector<std::size_t> left_over;  // the pieces this round's groups did not take
    // The pieces of each group, in order: the first starts the group, the others are united into it.
    std::vector<std::vector<std::size_t>> candidates;
    for (std::size_t i : round) {
      auto& g = group_of[linked.find(i)];
      if (g < 0) {
        g = static_cast<std::ptrdiff_t>(candidates.size());
        candidates.emplace_back();
      }
      candidates[static_cast<std::size_t>(g)].push_back(i);
    }
    groups.resize(candidates.size());
    std::size_t most = 0;  // unions the groups may need
    for (const auto& c : candidates) most += c.size() - 1;
    if (most <= budget) {
      // Within the budget, the groups are made side by side: no group's unions depend on another's.
      std::vector<std::vector<std::size_t>> left(groups.size());
      std::vector<std::size_t> attempts(groups.size(), 0);
      // A group made by an earlier call, of the same pieces, is taken as it was made.
      std::vector<std::vector<std::vector<double>>> key(groups.size());
      std::vector<char> reused(groups.size(), 0);
      for (std::size_t g = 0; made && g < groups.size(); ++g) {
        const auto& c = candidates[g];
        if (c.size() < 2) continue;
        for (std::size_t i : c) key[g].push_back(shape_of(pieces[i]));
        const auto it = made->store().made.find(key[g]);
        if (it == made->store().made.end()) continue;
        const auto& m = it->second;
        groups[g].surface = m.surface;
        for (std::size_t k : m.taken) groups[g].members.push_back(c[k]);
        for (std::size_t k : m.left) left[g].push_back(c[k]);
        attempts[g] = m.attempts;
        reused[g] = 1;
      }
      tbb::parallel_for(std::size_t{0}, groups.size(), [&](std::size_t g) {
        if (reused[g]) return;
        const auto& c = candidates[g];
        groups[g] = {surfaces[c.front()], {c.front()}};
        for (std::size_t k = 1; k < c.size(); ++k) {
          if (groups[g].members.size() < kMaxGroup) {
            ++attempts[g];
            if (unite_into(groups[g].surface, surfaces[c[k]])) {
              groups[g].members.push_back(c[k]);
              continue;
            }
          }
          left[g].push_back(c[k]);
        }
      });
      for (std::size_t g = 0; g < groups.size(); ++g) {
        left_over.insert(left_over.end(), left[g].begin(), left[g].end());
        budget -= attempts[g];  // as if made again: the same budget, the same mesh
        if (reused[g]) continue;
        out.batches += attempts[g];
        if (!made || candidates[g].size() < 2) continue;
        const auto& c = candidates[g];
        auto position = [&](std::size_t i) { return static_cast<std::size_t>(std::find(c.begin(), c.end(), i) - c.begin()); };
        GroupUnions::Store::Made m{groups[g].surface, {}, {}, attempts[g]};
        for (std::size_t i : groups[g].members) m.taken.push_back(position(i));
        for (std::size_t i : left[g]) m.left.push_back(position(i));
        made->store().made.emplace(std::move(key[g]), std::move(m));
      }
      std::sort(left_over.begin(), left_over.end());  // in the order of the pieces, as one at a time
    } else {
      // The budget may run out: one piece at a time, in their order, each drawing on it.
      for (std::size_t g = 0; g < groups.size(); ++g) groups[g] = {surfaces[candidates[g].front()], {candidates[g].front()}};
      for (std::size_t i : round) {
        auto& into = groups[static_cast<std::size_t>(group_of[linked.find(i)])];
        if (into.members.front() == i) continue;
        if (into.members.size() < kMaxGroup && try_unite(into.surface, surfaces[i])) into.members.push_back(i);
        else left_over.push_back(i);
      }
    }
    bool taken = false;  // the whole took this round's groups in one corefinement
    if (!groups.empty()) {
      Surface together;
      std::vector<std::size_t> members;
      for (const auto& g : groups) {
        together.join(g.surface);
        members.insert(members.end(), g.members.begin(), g.members.end());
      }
      if (whole.unite(std::move(together), members, out.batches)) {
        out.united += members.size();
        taken = true;
      } else {
        // One group at a time, and the pieces of a group the whole refuses one at a time.
        for (const auto& g : groups) {
          if (groups.size() > 1 && budget == 0) {
            out.skipped += g.members.size();
            continue;
          }
          if (groups.size() > 1 && try_unite_whole(g.surface, g.members)) {
            out.united += g.members.size();
            continue;
          }
          if (g.members.size() > 1) left_over.insert(left_over.end(), g.members.begin(), g.members.end());
          else keep_apart(g.surface, 1);
        }
      }
    }
    again = taken && left_over.size() >= 2 && left_over.size() < round.size() && budget > 0;
    if (again) round = std::move(left_over);
    else alone = std::move(left_over);
  }
  // The pieces left to unite with the whole (a group was full, or refused them) go in layers: in one
  // layer no two boxes overlap, so its pieces neither cross nor hold one another and the layer is
  // one corefinement with the whole. (One at a time, each cost a corefinement of the whole tree:
  // twenty of them took 7 s of a 22 s model of a pine of the LPine1 plot.)
  std::vector<std::vector<std::size_t>> layers;
  for (std::size_t i : alone) {
    auto apart_from = [&](const std::vector<std::size_t>& layer) {
      return std::none_of(layer.begin(), layer.end(), [&](std::size_t j) { return boxes[i].intersects(boxes[j]); });
    };
    const auto layer = std::find_if(layers.begin(), layers.end(), apart_from);
    if (layer == layers.end()) layers.push_back({i});
    else layer->push_back(i);
  }
  for (const auto& layer : layers) {
    if (layer.size() > 1 && budget > 0) {
      Surface together;
      for (std::size_t i : layer) together.join(surfaces[i]);
      if (try_unite_whole(std::move(together), layer)) {
        out.united += layer.size();
        continue;
      }
    }
    for (std::size_t i : layer) {  // alone, or the layer refused: one at a time
      if (budget == 0) ++out.skipped;
      else if (try_unite_whole(surfaces[i], {i})) ++out.united;
      else keep_apart(surfaces[i], 1);
    }
  }
  whole.surface().collect_garbage();
  out.voids = fill_voids(whole.surface());
  if (apart.number_of_faces() > 0) out.apart = to_tree_mesh(apart, offset);
  // The exact points rounded to what 32-bit floats hold in the input's frame, where most formats and
  // MeshLab keep them: a file then holds the mesh that was checked.
  out.mesh = to_tree_mesh(whole.surface(), offset);
  if (out.batches > 0 || out.united > 0) out.welded = weld_short_edges(out.mesh, weld, where);
  return out;
}

}  // namespace treeskel::modeling::detail
