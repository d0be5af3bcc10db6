// Speed of the tree model stages: radii (pipe model) and the swept mesh, on a synthetic skeleton of
// a chosen size, and the whole model (read, skeleton, radii, mesh, check, GLB) on cloud files.
//
//   bench_model [--nodes N] [--repeat R] [FILE...]
//
// The synthetic skeleton is a random tree (eval::grow_tree) whose segments are refined until it has
// at least N nodes; its radii are its own cylinders' (the fit treats them as measurements). Prints
// Markdown tables (best of R runs).
#include "huge_pages.h"
#include "treeskel/eval/tree_generator.h"
#include "treeskel/io/mesh_io.h"
#include "treeskel/io/point_cloud_io.h"
#include "treeskel/modeling/measurements.h"
#include "treeskel/modeling/radii.h"
#include "treeskel/modeling/sweep.h"
#include "treeskel/pipeline.h"

#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace treeskel;

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

/// A grown tree as a skeleton: one node at the base and one at the end of every cylinder.
Skeleton skeleton_of(const eval::GrownTree& tree) {
  Skeleton s;
  SkeletonNode base;
  base.position = tree.cylinders.front().a;
  base.radius = tree.cylinders.front().radius_a;
  s.root = add_node(s, base);
  std::vector<NodeId> end(tree.cylinders.size());
  for (std::size_t i = 0; i < tree.cylinders.size(); ++i) {
    SkeletonNode n;
    n.position = tree.cylinders[i].b;
    n.radius = tree.cylinders[i].radius_b;
    end[i] = add_node(s, n);
    boost::add_edge(tree.parent[i] < 0 ? s.root : end[static_cast<std::size_t>(tree.parent[i])], end[i], s.graph);
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  treeskel::cli::restart_with_huge_pages(argv, treeskel::cli::Memory::reuse_only);  // as `treeskel model` has it
  std::size_t nodes = 10000;
  int repeat = 3;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--nodes" && i + 1 < argc) nodes = std::stoul(argv[++i]);
    else if (a == "--repeat" && i + 1 < argc) repeat = std::stoi(argv[++i]);
    else if (a == "-h" || a == "--help") {
      std::cout << "usage: bench_model [--nodes N] [--repeat R] [FILE...]\n";
      return 0;
    } else files.push_back(a);
  }

  eval::GrowOptions grow;
  grow.orders = 4;
  Skeleton skeleton = skeleton_of(eval::grow_tree(grow));
  while (skeleton.node_count() < nodes) {
    grow.segment_length *= 0.7;
    skeleton = skeleton_of(eval::grow_tree(grow));
  }
  double radii = 1e300, sweep = 1e300, sweep_no_repair = 1e300;
  modeling::TreeMesh mesh;
  modeling::SweepStats stats;  // of the run whose mesh took least
  for (int r = 0; r < repeat; ++r) {
    Skeleton s = skeleton;
    double t = now();
    modeling::fit_radii(s, nullptr);
    radii = std::min(radii, now() - t);
    t = now();
    modeling::SweepStats st;
    mesh = modeling::sweep_mesh(s, {}, &st);
    const double took = now() - t;
    if (took < sweep) {
      sweep = took;
      stats = st;
    }
    modeling::SweepOptions fast;
    fast.repair = false;
    t = now();
    modeling::sweep_mesh(s, fast);
    sweep_no_repair = std::min(sweep_no_repair, now() - t);
  }
  const modeling::MeshCheck check = modeling::check_mesh(mesh, false);
  std::printf("| skeleton nodes | radii | mesh (with the self-intersection test) | of it: sweep (tests) / pieces / unions | mesh (no repair: those limbs left out) | triangles | valid |\n");
  std::printf("|---:|---:|---:|---|---:|---:|---|\n");
  std::printf("| %zu | %.3f s | %.3f s | %.3f (%.3f) / %.3f / %.3f s | %.3f s | %zu | %s |\n\n", skeleton.node_count(), radii, sweep,
              stats.sweep_seconds, stats.test_seconds, stats.pieces_seconds, stats.union_seconds, sweep_no_repair,
              check.faces, check.ok() && stats.self_intersections == 0 ? "yes" : check.problem().c_str());
  std::printf("(built %d times: %d repair rounds; %zu branches thinned, %zu swept apart and united, %zu twigs inside joins)\n\n",
              stats.attempts, stats.repair_rounds, stats.joins_thinned + stats.repaired_shrunk,
              stats.joins_dropped + stats.repaired_dropped, stats.twigs_absorbed);

  if (files.empty()) return 0;
  std::printf("| file | points | read | skeleton | radii | mesh | of it: sweep (tests) / pieces / unions | measure + GLB | total | triangles |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---|---:|---:|---:|\n");
  const fs::path out = fs::temp_directory_path() / "bench_model.glb";
  for (const auto& file : files) {
    double best[6] = {1e300, 1e300, 1e300, 1e300, 1e300, 1e300};
    std::size_t points = 0, faces = 0;
    modeling::SweepStats split;  // of the run whose mesh took least
    for (int r = 0; r < repeat; ++r) {
      double t0 = now();
      const PointCloud cloud = io::read_point_cloud(file);
      const double t1 = now();
      SkeletonOptions as_model;  // pruned as `treeskel model` prunes
      modeling::use_model_pruning(as_model.prune);
      SkeletonStats skeleton_stats;
      Skeleton s = extract_skeleton(cloud, as_model, &skeleton_stats);
      const double t2 = now();
      modeling::RadiusOptions radii;  // as `treeskel model` fits them: with the octree's cell
      radii.cell_size = skeleton_stats.cell_size;
      modeling::fit_radii(s, &cloud, radii);
      const double t3 = now();
      modeling::SweepStats st;
      modeling::SweepOptions sweep;  // in the frame the GLB holds, as `treeskel model -o x.glb` sweeps
      sweep.local_floats = io::holds_local_floats(out);
      const modeling::TreeMesh m = modeling::sweep_mesh(s, sweep, &st);
      const double t4 = now();
      if (t4 - t3 < best[3]) split = st;
      modeling::measure_tree(s, &cloud);
      io::write_mesh(out, m, s.offset);
      const double t5 = now();
      const double times[6] = {t1 - t0, t2 - t1, t3 - t2, t4 - t3, t5 - t4, t5 - t0};
      for (int k = 0; k < 6; ++k) best[k] = std::min(best[k], times[k]);
      points = cloud.size();
      faces = m.n_faces();
    }
    std::printf("| %s | %zu | %.2f s | %.2f s | %.2f s | %.2f s | %.2f (%.2f) / %.2f / %.2f s | %.2f s | %.2f s | %zu |\n",
                fs::path(file).filename().c_str(), points, best[0], best[1], best[2], best[3], split.sweep_seconds,
                split.test_seconds, split.pieces_seconds, split.union_seconds, best[4], best[5], faces);
  }
  fs::remove(out);
  struct rusage usage {};
  ::getrusage(RUSAGE_SELF, &usage);
  std::printf("\npeak memory of the whole run: %.0f MB\n", static_cast<double>(usage.ru_maxrss) / 1024.0);
  return 0;
}
