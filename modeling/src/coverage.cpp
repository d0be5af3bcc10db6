#include "treeskel/modeling/coverage.h"

#include "face_tree.h"
#include "treeskel/geometry.h"

#include <CGAL/boost/graph/property_maps.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <random>
#include <utility>
#include <vector>

namespace treeskel::modeling {

namespace {

using detail::FaceTree;
using K = detail::GT;

K::Point_3 point(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }

/// wood_inside's draw: the frustums' volume into `wood`, and `samples` points drawn uniformly in it
/// (none when no frustum has a volume).
std::vector<K::Point_3> draw_in_frustums(const Skeleton& skeleton, std::size_t samples, std::uint64_t seed,
                                         WoodInside& wood) {
  const auto& g = skeleton.graph;
  // Each edge's frustum and the running sum of their volumes, to draw an edge by its share.
  struct Frustum {
    Eigen::Vector3d a, b;
    double ra, rb;
  };
  std::vector<Frustum> frustums;
  std::vector<double> upto;
  for (auto [it, end] = boost::edges(g); it != end; ++it) {
    const NodeId u = boost::source(*it, g), v = boost::target(*it, g);
    const Frustum f{g[u].position, g[v].position, std::max(g[u].radius, 0.0), std::max(g[v].radius, 0.0)};
    const double volume = frustum_volume(f.ra, f.rb, (f.b - f.a).norm());
    if (!(volume > 0.0)) continue;
    wood.volume += volume;
    frustums.push_back(f);
    upto.push_back(wood.volume);
  }
  if (frustums.empty() || samples == 0) return {};
  // The points first, from one generator in order; then the tests, side by side.
  std::mt19937_64 random(seed);
  auto uniform = [&random] { return static_cast<double>(random() >> 11) * 0x1.0p-53; };
  std::vector<K::Point_3> points;
  points.reserve(samples);
  while (points.size() < samples) {
    const std::size_t e = static_cast<std::size_t>(
        std::upper_bound(upto.begin(), upto.end(), uniform() * wood.volume) - upto.begin());
    const Frustum& f = frustums[std::min(e, frustums.size() - 1)];
    // Along the axis with density as the cross section (r linear in t, so r² by rejection), then
    // uniformly in the disc there.
    const double t = uniform(), r = f.ra + (f.rb - f.ra) * t, r_max = std::max(f.ra, f.rb);
    if (uniform() * r_max * r_max > r * r) continue;
    const Eigen::Vector3d axis = (f.b - f.a).normalized();
    const Eigen::Vector3d across = axis.unitOrthogonal(), other = axis.cross(across);
    const double angle = 2.0 * kPi * uniform(), rho = r * std::sqrt(uniform());
    points.push_back(point(f.a + (f.b - f.a) * t + rho * (std::cos(angle) * across + std::sin(angle) * other)));
  }
  return points;
}

/// Counts those of `points` inside the mesh of `tree` (built) into `wood`.
void count_inside(const FaceTree& tree, const std::vector<K::Point_3>& points, WoodInside& wood) {
  const detail::SideOfFaces side(tree);
  std::vector<char> in(points.size(), 0);
  tbb::parallel_for(std::size_t{0}, points.size(), [&](std::size_t i) { in[i] = side(points[i]) != CGAL::ON_UNBOUNDED_SIDE; });
  wood.inside = static_cast<std::size_t>(std::count(in.begin(), in.end(), 1));
}

}  // namespace

SkeletonCoverage skeleton_coverage(const Skeleton& skeleton, const TreeMesh& mesh, double step, double tolerance,
                                   std::size_t wood_samples) {
  SkeletonCoverage out;
  const auto& g = skeleton.graph;
  if (boost::num_vertices(g) == 0) return out;
  Eigen::AlignedBox3d box;
  for (NodeId v = 0; v < boost::num_vertices(g); ++v) box.extend(g[v].position);
  const double extent = std::max(box.sizes().maxCoeff(), 1e-300);
  if (!(step > 0.0)) step = extent / 2000.0;
  if (!(tolerance > 0.0)) tolerance = 1e-6 * extent;
  for (auto [it, end] = boost::edges(g); it != end; ++it)
    out.length += (g[boost::source(*it, g)].position - g[boost::target(*it, g)].position).norm();
  const std::vector<K::Point_3> wood = draw_in_frustums(skeleton, wood_samples, 1, out.wood);
  out.wood.samples = wood.size();
  if (mesh.n_faces() == 0) return out;
  FaceTree tree(faces(mesh).first, faces(mesh).second, mesh);
  tree.build();  // before the threads read it
  count_inside(tree, wood, out.wood);
  const detail::SideOfFaces inside(tree);
  const double tolerance2 = tolerance * tolerance;
  // Each edge on its own (the tree is only read), summed in edge order: the same share for any
  // number of threads. First which samples lie inside; then, for those outside, whether they are
  // within the tolerance of the surface.
  std::vector<std::pair<NodeId, NodeId>> edges;
  for (auto [it, end] = boost::edges(g); it != end; ++it) edges.emplace_back(boost::source(*it, g), boost::target(*it, g));
  std::vector<int> pieces(edges.size()), hits(edges.size(), 0);
  std::vector<std::vector<K::Point_3>> outside(edges.size());
  tbb::parallel_for(std::size_t{0}, edges.size(), [&](std::size_t e) {
    const Eigen::Vector3d a = g[edges[e].first].position, b = g[edges[e].second].position;
    // Samples at the centres of equal pieces: each stands for one piece's length.
    pieces[e] = std::max(2, static_cast<int>(std::ceil((b - a).norm() / step)));
    // A sample is on the side of the one before it when the segment between them meets no triangle
    // (an exact predicate, as is the side test): only the first sample, one past the surface and one
    // after a sample outside is tested on its own. Most samples lie deep inside a branch, and a short
    // segment is far cheaper to test than a ray's parity.
    K::Point_3 last;
    bool last_inside = false;
    for (int i = 0; i < pieces[e]; ++i) {
      const K::Point_3 q = point(a + (b - a) * ((i + 0.5) / pieces[e]));
      const bool in = (i > 0 && last_inside && !tree.do_intersect(K::Segment_3(last, q))) ||
                      inside(q) != CGAL::ON_UNBOUNDED_SIDE;
      if (in) ++hits[e];
      else outside[e].push_back(q);
      last = q;
      last_inside = in;
    }
  });
  std::size_t outside_count = 0;
  for (const auto& o : outside) outside_count += o.size();
  if (outside_count > 0) {
    // A sample outside is covered when a triangle lies within the tolerance: only the triangles that
    // meet a box around it are measured (few samples lie outside; a structure for nearest-triangle
    // queries over the whole mesh cost more to build than they take to answer). The box is a little
    // larger than the tolerance, so that rounding in the distances cannot leave a triangle out.
    const double reach = 1.001 * tolerance;
    const CGAL::Triangle_from_face_descriptor_map<TreeMesh, detail::VPM> triangle(&mesh, get(CGAL::vertex_point, mesh));
    tbb::parallel_for(std::size_t{0}, edges.size(), [&](std::size_t e) {
      std::vector<TreeMesh::FaceHandle> near;
      for (const auto& q : outside[e]) {
        near.clear();
        const CGAL::Bbox_3 box(q.x() - reach, q.y() - reach, q.z() - reach, q.x() + reach, q.y() + reach, q.z() + reach);
        tree.all_intersected_primitives(box, std::back_inserter(near));
        const bool close = std::any_of(near.begin(), near.end(), [&](TreeMesh::FaceHandle f) {
          return CGAL::squared_distance(q, get(triangle, f)) <= tolerance2;
        });
        if (close) ++hits[e];
      }
    });
  }
  std::vector<double> covered_length(edges.size(), 0.0);
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const double length = (g[edges[e].second].position - g[edges[e].first].position).norm();
    covered_length[e] = length * hits[e] / pieces[e];
  }
  for (double x : covered_length) out.inside_length += x;
  return out;
}

WoodInside wood_inside(const Skeleton& skeleton, const TreeMesh& mesh, std::size_t samples, std::uint64_t seed) {
  WoodInside out;
  const std::vector<K::Point_3> points = draw_in_frustums(skeleton, samples, seed, out);
  out.samples = points.size();
  if (points.empty() || mesh.n_faces() == 0) return out;  // an empty mesh holds none of it
  FaceTree tree(faces(mesh).first, faces(mesh).second, mesh);
  tree.build();  // before the threads read it
  count_inside(tree, points, out);
  return out;
}

std::vector<double> surface_distances(const TreeMesh& mesh, const std::vector<Eigen::Vector3d>& points) {
  std::vector<double> out(points.size(), std::numeric_limits<double>::infinity());
  if (mesh.n_faces() == 0) return out;
  FaceTree tree(faces(mesh).first, faces(mesh).second, mesh);
  tree.accelerate_distance_queries();
  for (std::size_t i = 0; i < points.size(); ++i) out[i] = std::sqrt(tree.squared_distance(point(points[i])));
  return out;
}

double share_within(const std::vector<double>& distances, double limit) {
  if (distances.empty()) return 0.0;
  const auto n = std::count_if(distances.begin(), distances.end(), [&](double d) { return d <= limit; });
  return static_cast<double>(n) / static_cast<double>(distances.size());
}

}  // namespace treeskel::modeling
