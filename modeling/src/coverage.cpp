#include "treeskel/modeling/coverage.h"

#include "surface_mesh.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace treeskel::modeling {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Surface = CGAL::Surface_mesh<K::Point_3>;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<Surface>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

Surface to_surface(const TreeMesh& mesh) {
  Surface out;
  detail::append_to_surface(out, mesh);
  return out;
}

K::Point_3 point(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }

}  // namespace

SkeletonCoverage skeleton_coverage(const Skeleton& skeleton, const TreeMesh& mesh, double step, double tolerance) {
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
  if (mesh.n_faces() == 0) return out;
  const Surface surface = to_surface(mesh);
  Tree tree(faces(surface).first, faces(surface).second, surface);
  tree.build();  // before the threads read it
  const CGAL::Side_of_triangle_mesh<Surface, K> inside(tree);
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
    tree.accelerate_distance_queries();  // built only when a sample needs a distance
    tbb::parallel_for(std::size_t{0}, edges.size(), [&](std::size_t e) {
      for (const auto& q : outside[e]) hits[e] += tree.squared_distance(q) <= tolerance2 ? 1 : 0;
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

std::vector<double> surface_distances(const TreeMesh& mesh, const std::vector<Eigen::Vector3d>& points) {
  std::vector<double> out(points.size(), std::numeric_limits<double>::infinity());
  if (mesh.n_faces() == 0) return out;
  const Surface surface = to_surface(mesh);
  Tree tree(faces(surface).first, faces(surface).second, surface);
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
