// How much of a real cloud a tree model shows, as a person judging it over its scan would see it:
//
//   bench_coverage [--up z] [--truth SKELETON] [--check] CLOUD MESH
//
// CLOUD is read as treeskel reads it (its local frame), MESH as a viewer reads it (assimp); write
// the mesh with `treeskel model CLOUD --local -o MESH.ply` so that both are in the same frame.
// Prints one line: the share of the cloud's points within 1% and within 2% of the cloud's height
// from the mesh's surface (exact point-to-triangle distances), and the reach: the mesh's extent
// along the up axis over the cloud's. With --truth (a synthetic tree's true skeleton, as `treeskel
// synth` writes it), also the share of the true skeleton's length inside the mesh, and within 1% of
// the height of its surface: the mesh holds every true branch the skeleton found. With --check, also
// the file's own checks as a reader meets it: closed and manifold once equal positions are one
// vertex (a file that is not is refused with the face that breaks it), its components and its
// self-intersections, the whole mesh tested exactly.
#include "treeskel/io/mesh_io.h"
#include "treeskel/io/point_cloud_io.h"
#include "treeskel/io/skeleton_io.h"
#include "treeskel/modeling/coverage.h"

#include <cstdio>
#include <exception>
#include <iostream>
#include <string>

using namespace treeskel;

int main(int argc, char** argv) {
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  std::vector<std::string> files;
  std::string truth_file;
  bool check_file = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--up" && i + 1 < argc) {
      const std::string axis = argv[++i];
      up = axis == "x" ? Eigen::Vector3d::UnitX() : axis == "y" ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ();
    } else if (a == "--truth" && i + 1 < argc) {
      truth_file = argv[++i];
    } else if (a == "--check") {
      check_file = true;
    } else {
      files.push_back(a);
    }
  }
  if (files.size() != 2) {
    std::cerr << "usage: bench_coverage [--up x|y|z] [--truth SKELETON] [--check] CLOUD MESH\n";
    return 2;
  }
  try {
    const PointCloud cloud = io::read_point_cloud(files[0]);
    const modeling::TreeMesh mesh = io::read_mesh(files[1]);
    double lo = 1e300, hi = -1e300, mesh_lo = 1e300, mesh_hi = -1e300;
    for (const auto& p : cloud.positions) {
      lo = std::min(lo, p.dot(up));
      hi = std::max(hi, p.dot(up));
    }
    for (auto v : mesh.vertices()) {
      const auto p = mesh.point(v);
      const double h = Eigen::Vector3d(p[0], p[1], p[2]).dot(up);
      mesh_lo = std::min(mesh_lo, h);
      mesh_hi = std::max(mesh_hi, h);
    }
    const double height = hi - lo;
    const auto d = modeling::surface_distances(mesh, cloud.positions);
    std::printf("%zu points, height %.3f: within 1%% %.3f, within 2%% %.3f, reach %.3f\n", cloud.size(), height,
                modeling::share_within(d, 0.01 * height), modeling::share_within(d, 0.02 * height),
                (mesh_hi - mesh_lo) / height);
    if (check_file) {
      // The file as a reader meets it (positions that are equal in it are one vertex), checked whole.
      const modeling::MeshCheck check = modeling::check_mesh(mesh, true);
      std::printf("file: %s, %zu components, %zu self-intersections\n",
                  check.boundary_edges == 0 ? "closed and manifold" : "not closed", check.components, check.self_intersections);
    }
    if (!truth_file.empty()) {
      // The true skeleton in the cloud's local frame, as the mesh is.
      Skeleton truth = io::read_skeleton(truth_file);
      const Eigen::Vector3d shift = truth.offset - cloud.offset;
      for (NodeId v = 0; v < truth.node_count(); ++v) truth[v].position += shift;
      const auto inside = modeling::skeleton_coverage(truth, mesh);
      const auto near = modeling::skeleton_coverage(truth, mesh, 0.0, 0.01 * height);
      std::printf("truth: length %.3f, inside the mesh %.3f, within 1%% of its surface %.3f\n", inside.length,
                  inside.share(), near.share());
    }
  } catch (const std::exception& e) {
    std::cerr << "bench_coverage: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
