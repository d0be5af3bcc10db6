// How much of a real cloud a tree model shows, as a person judging it over its scan would see it:
//
//   bench_coverage [--up z] [--truth SKELETON] [--skeleton SKELETON] [--check] [--frame MODELLED] [--precision]
//                  [--missed OUT.xyz] CLOUD MESH
//
// CLOUD is read as treeskel reads it (its local frame), MESH as a viewer reads it (assimp); write
// the mesh with `treeskel model CLOUD --local -o MESH.ply` so that both are in the same frame. With
// --frame, CLOUD is another cloud of the same place (the true wood of a tree, say) and MESH was
// written by `treeskel model MODELLED --local`: CLOUD is moved into MODELLED's local frame.
// Prints one line: the share of the cloud's points within 1% and within 2% of the cloud's height
// from the mesh's surface (exact point-to-triangle distances), and the reach: the mesh's extent
// along the up axis over the cloud's. With --truth (a synthetic tree's true skeleton, as `treeskel
// synth` writes it), also the share of the true skeleton's length inside the mesh, and within 1% of
// the height of its surface: the mesh holds every true branch the skeleton found. With --check, also
// the file's own checks as a reader meets it: closed and manifold once equal positions are one
// vertex (a file that is not is refused with the face that breaks it), its components and its
// self-intersections, the whole mesh tested exactly. With --precision, also the share of the mesh's
// vertices within 1% and 2% of the height from CLOUD's nearest point: how little of the model lies
// where the cloud has no points (in the leaves, when CLOUD is a tree's true wood). With --missed, the
// points farther than 2% of the height from the surface are written to OUT.xyz (in CLOUD's local
// frame, x y z and the distance), to look at beside the mesh. With --skeleton (the skeleton the mesh
// was swept along, as `treeskel model --skeleton` writes it), also the share of the cloud's points
// within 1% and 2% of the height from the skeleton's axis (exact point-to-segment distances), and of
// the points farther than 2% from the mesh, the share within 2% of the skeleton: what the mesh lost of
// what the skeleton reached. A point the skeleton does not come near is the skeleton's loss, not the
// mesh's. With --skeleton and a mesh, also the wood inside: the share of the skeleton's frustums'
// volume (its radii, as the report's wood volume) that lies inside the mesh, from 4,000 seeded
// samples; unlike the mesh's volume over the frustums', an overlap of frustums does not lower it.
// `bench_coverage [--up z] --skeleton SKELETON CLOUD` (no mesh) prints the skeleton's two shares
// alone: how near a skeleton (`skeletonize`'s, say) comes to the points (bench/skeleton_reach.sh).
#include "treeskel/geometry.h"
#include "treeskel/io/mesh_io.h"
#include "treeskel/io/point_cloud_io.h"
#include "treeskel/io/skeleton_io.h"
#include "treeskel/kd_search.h"
#include "treeskel/modeling/coverage.h"

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <exception>
#include <iostream>
#include <limits>
#include <stdexcept>
#include <string>

using namespace treeskel;

namespace {

/// Per point, its distance to the nearest edge of `skeleton`. The edges are sampled every `spacing`
/// and the edges of a point's eight nearest samples are measured exactly; the nearest edge's nearest
/// sample lies within half a spacing of it, so an edge missed that way is at most that much nearer.
std::vector<double> axis_distances(const Skeleton& skeleton, const std::vector<Eigen::Vector3d>& points, double spacing) {
  std::vector<kd::Point> samples;
  std::vector<std::pair<NodeId, NodeId>> edge_of;
  for (auto [e, end] = boost::edges(skeleton.graph); e != end; ++e) {
    const NodeId a = boost::source(*e, skeleton.graph), b = boost::target(*e, skeleton.graph);
    const Eigen::Vector3d pa = skeleton[a].position, pb = skeleton[b].position;
    const int steps = std::max(1, static_cast<int>(std::ceil((pb - pa).norm() / spacing)));
    for (int k = 0; k <= steps; ++k) {
      const Eigen::Vector3d q = pa + (pb - pa) * (static_cast<double>(k) / steps);
      samples.emplace_back(q.x(), q.y(), q.z());
      edge_of.emplace_back(a, b);
    }
  }
  if (samples.empty()) throw std::runtime_error("the skeleton has no edge");
  std::vector<std::uint32_t> ids(samples.size());
  for (std::uint32_t i = 0; i < ids.size(); ++i) ids[i] = i;
  const kd::Tree tree(ids.begin(), ids.end(), kd::Tree::Splitter(), kd::Traits(kd::PointMap(samples.data())));
  std::vector<double> d(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    const kd::KnnSearch search(tree, kd::Point(p.x(), p.y(), p.z()), 8, 0, true, kd::KnnSearch::Distance(kd::PointMap(samples.data())));
    double best = std::numeric_limits<double>::infinity();
    for (const auto& [id, d2] : search) {
      const auto [a, b] = edge_of[id];
      best = std::min(best, point_segment_distance(p, skeleton[a].position, skeleton[b].position));
    }
    d[i] = best;
  }
  return d;
}

}  // namespace

/// The skeleton in `file`, moved into the cloud's local frame (as the mesh is).
Skeleton skeleton_in_frame_of(const std::string& file, const PointCloud& cloud) {
  Skeleton skeleton = io::read_skeleton(file);
  const Eigen::Vector3d shift = skeleton.offset - cloud.offset;
  for (NodeId v = 0; v < skeleton.node_count(); ++v) skeleton[v].position += shift;
  return skeleton;
}

int main(int argc, char** argv) {
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  std::vector<std::string> files;
  std::string truth_file, frame_file, missed_file, skeleton_file;
  bool check_file = false, precision = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--up" && i + 1 < argc) {
      const std::string axis = argv[++i];
      up = axis == "x" ? Eigen::Vector3d::UnitX() : axis == "y" ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ();
    } else if (a == "--truth" && i + 1 < argc) {
      truth_file = argv[++i];
    } else if (a == "--skeleton" && i + 1 < argc) {
      skeleton_file = argv[++i];
    } else if (a == "--check") {
      check_file = true;
    } else if (a == "--frame" && i + 1 < argc) {
      frame_file = argv[++i];
    } else if (a == "--missed" && i + 1 < argc) {
      missed_file = argv[++i];
    } else if (a == "--precision") {
      precision = true;
    } else {
      files.push_back(a);
    }
  }
  // With --skeleton and no mesh: the skeleton's line alone (how near a skeleton, e.g. skeletonize's,
  // comes to the cloud's points).
  const bool skeleton_only = files.size() == 1 && !skeleton_file.empty() && truth_file.empty() && !check_file &&
                             !precision && missed_file.empty();
  if (files.size() != 2 && !skeleton_only) {
    std::cerr << "usage: bench_coverage [--up x|y|z] [--truth SKELETON] [--skeleton SKELETON] [--check] [--frame MODELLED] [--precision]\n"
                 "                      [--missed OUT.xyz] CLOUD MESH\n"
                 "       bench_coverage [--up x|y|z] --skeleton SKELETON CLOUD\n";
    return 2;
  }
  try {
    PointCloud cloud = io::read_point_cloud(files[0]);
    if (!frame_file.empty()) {  // into the local frame of the cloud the mesh was made from
      const Eigen::Vector3d shift = cloud.offset - io::read_point_cloud(frame_file).offset;
      for (auto& p : cloud.positions) p += shift;
    }
    double lo = 1e300, hi = -1e300, mesh_lo = 1e300, mesh_hi = -1e300;
    Eigen::AlignedBox3d cloud_box, mesh_box;
    for (const auto& p : cloud.positions) {
      lo = std::min(lo, p.dot(up));
      hi = std::max(hi, p.dot(up));
      cloud_box.extend(p);
    }
    if (skeleton_only) {
      const auto axis = axis_distances(skeleton_in_frame_of(skeleton_file, cloud), cloud.positions, 0.001 * (hi - lo));
      std::printf("skeleton: within 1%% %.3f, within 2%% %.3f\n", modeling::share_within(axis, 0.01 * (hi - lo)),
                  modeling::share_within(axis, 0.02 * (hi - lo)));
      return 0;
    }
    const modeling::TreeMesh mesh = io::read_mesh(files[1]);
    for (auto v : mesh.vertices()) {
      const auto p = mesh.point(v);
      const Eigen::Vector3d q(p[0], p[1], p[2]);
      mesh_lo = std::min(mesh_lo, q.dot(up));
      mesh_hi = std::max(mesh_hi, q.dot(up));
      mesh_box.extend(q);
    }
    // A mesh written in another frame (a georeferenced cloud's OBJ in world coordinates, without
    // --local) lies far from the cloud: every share would read 0, as if nothing were covered.
    Eigen::AlignedBox3d near = cloud_box;
    near.min().array() -= 0.1 * cloud_box.sizes().maxCoeff();
    near.max().array() += 0.1 * cloud_box.sizes().maxCoeff();
    if (mesh.n_vertices() == 0 || !near.intersects(mesh_box))
      throw std::runtime_error("the mesh does not overlap the cloud (its centre lies " +
                               std::to_string((mesh_box.center() - cloud_box.center()).norm()) +
                               " from the cloud's): it was written in another frame; write it with `treeskel model CLOUD --local`");
    const double height = hi - lo;
    const auto d = modeling::surface_distances(mesh, cloud.positions);
    std::printf("%zu points, height %.3f: within 1%% %.3f, within 2%% %.3f, reach %.3f\n", cloud.size(), height,
                modeling::share_within(d, 0.01 * height), modeling::share_within(d, 0.02 * height),
                (mesh_hi - mesh_lo) / height);
    if (!missed_file.empty()) {
      std::FILE* out = std::fopen(missed_file.c_str(), "w");
      if (out == nullptr) throw std::runtime_error("cannot write " + missed_file);
      for (std::size_t i = 0; i < d.size(); ++i) {
        const auto& p = cloud.positions[i];
        if (d[i] > 0.02 * height) std::fprintf(out, "%.4f %.4f %.4f %.4f\n", p.x(), p.y(), p.z(), d[i]);
      }
      if (std::fclose(out) != 0) throw std::runtime_error("cannot write " + missed_file);
    }
    if (!skeleton_file.empty()) {
      const Skeleton skeleton = skeleton_in_frame_of(skeleton_file, cloud);
      const auto axis = axis_distances(skeleton, cloud.positions, 0.001 * height);
      const modeling::WoodInside wood = modeling::wood_inside(skeleton, mesh);
      std::printf("wood: frustums %.6g, inside the mesh %.3f of %zu samples\n", wood.volume, wood.share(), wood.samples);
      std::size_t missed = 0, missed_near = 0;
      for (std::size_t i = 0; i < d.size(); ++i)
        if (d[i] > 0.02 * height) {
          ++missed;
          missed_near += axis[i] <= 0.02 * height;
        }
      std::printf("skeleton: within 1%% %.3f, within 2%% %.3f; of the %zu points farther than 2%% from the mesh, %.3f within 2%% of the skeleton\n",
                  modeling::share_within(axis, 0.01 * height), modeling::share_within(axis, 0.02 * height), missed,
                  missed == 0 ? 0.0 : static_cast<double>(missed_near) / static_cast<double>(missed));
    }
    if (precision) {
      std::vector<kd::Point> points;
      points.reserve(cloud.size());
      for (const auto& p : cloud.positions) points.emplace_back(p.x(), p.y(), p.z());
      std::vector<std::uint32_t> ids(points.size());
      for (std::uint32_t i = 0; i < ids.size(); ++i) ids[i] = i;
      const kd::Tree tree(ids.begin(), ids.end(), kd::Tree::Splitter(), kd::Traits(kd::PointMap(points.data())));
      std::size_t near1 = 0, near2 = 0, all = 0;
      for (auto v : mesh.vertices()) {
        const auto p = mesh.point(v);
        const kd::KnnSearch search(tree, kd::Point(p[0], p[1], p[2]), 1, 0, true, kd::KnnSearch::Distance(kd::PointMap(points.data())));
        const double d = std::sqrt(search.begin()->second);
        near1 += d <= 0.01 * height;
        near2 += d <= 0.02 * height;
        ++all;
      }
      std::printf("precision: %zu mesh vertices, within 1%% %.3f, within 2%% %.3f\n", all,
                  static_cast<double>(near1) / static_cast<double>(all), static_cast<double>(near2) / static_cast<double>(all));
    }
    if (check_file) {
      // The file as a reader meets it (positions that are equal in it are one vertex), checked whole.
      const modeling::MeshCheck check = modeling::check_mesh(mesh, true);
      std::printf("file: %s, %zu components, %zu self-intersections\n",
                  check.boundary_edges == 0 ? "closed and manifold" : "not closed", check.components, check.self_intersections);
    }
    if (!truth_file.empty()) {
      const Skeleton truth = skeleton_in_frame_of(truth_file, cloud);
      // The true skeleton's length alone: its wood is not printed, so none is drawn.
      const auto inside = modeling::skeleton_coverage(truth, mesh, 0.0, 0.0, 0);
      const auto near = modeling::skeleton_coverage(truth, mesh, 0.0, 0.01 * height, 0);
      std::printf("truth: length %.3f, inside the mesh %.3f, within 1%% of its surface %.3f\n", inside.length,
                  inside.share(), near.share());
    }
  } catch (const std::exception& e) {
    std::cerr << "bench_coverage: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
