// treeskel skeletonize INPUT -o OUTPUT
#include "commands.h"
#include "report.h"

#include "treeskel/error.h"
#include "treeskel/io/atomic_file.h"
#include "treeskel/io/point_cloud_io.h"
#include "treeskel/io/skeleton_io.h"
#include "treeskel/pipeline.h"

#include <nlohmann/json.hpp>
#include <sys/resource.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

namespace treeskel::cli {

namespace {

namespace fs = std::filesystem;

struct Settings {
  std::string input;
  std::string output;
  bool json = false;
  bool quiet = false;
  std::string up = "z";
  std::string root;
  std::string neighbours = "octree";
  SkeletonOptions options;
  bool no_prune = false, no_cpc = false, no_refine = false, no_junctions = false, no_smooth = false;
};

Eigen::Vector3d parse_vector(const std::string& text, const char* what) {
  std::string s = text;
  for (auto& c : s)
    if (c == ',') c = ' ';
  std::istringstream in(s);
  Eigen::Vector3d v;
  if (!(in >> v.x() >> v.y() >> v.z()) || !(in >> std::ws).eof())
    throw OptionError(std::string(what) + " must be three numbers 'x,y,z', got '" + text + "'");
  return v;
}

Eigen::Vector3d parse_up(const std::string& text) {
  if (text == "x" || text == "+x") return Eigen::Vector3d::UnitX();
  if (text == "y" || text == "+y") return Eigen::Vector3d::UnitY();
  if (text == "z" || text == "+z") return Eigen::Vector3d::UnitZ();
  if (text == "-x") return -Eigen::Vector3d::UnitX();
  if (text == "-y") return -Eigen::Vector3d::UnitY();
  if (text == "-z") return -Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d v = parse_vector(text, "--up");
  if (v.norm() == 0.0) throw OptionError("--up must not be the zero vector");
  return v.normalized();
}

int run(Settings& s) {
  Stopwatch clock;
  if (s.input.empty()) s.input = TREESKEL_DEFAULT_EXAMPLE;
  if (s.output.empty()) s.output = fs::path(s.input).stem().string() + "_skeleton.ply";
  const std::string out_ext = io::extension_of(s.output);
  if (out_ext != "ply" && out_ext != "obj" && out_ext != "json")
    throw OptionError(s.output + ": unknown skeleton extension '." + out_ext + "'; use .ply, .obj or .json");

  Progress progress(s.quiet || s.json);
  progress("reading " + fs::path(s.input).filename().string(), 0.0);
  const PointCloud cloud = io::read_point_cloud(s.input);

  SkeletonOptions& o = s.options;
  o.root.up = parse_up(s.up);
  if (!s.root.empty()) o.root.point = parse_vector(s.root, "--root") - cloud.offset;
  if (s.neighbours == "knn") o.graph.mode = NeighbourMode::knn;
  o.use_prune = !s.no_prune;
  o.use_cpc = !s.no_cpc;
  o.use_refine = !s.no_refine;
  o.use_junctions = !s.no_junctions;
  o.use_smooth = !s.no_smooth;
  if (progress.active()) o.progress = [&](const std::string& stage, double done) { progress(stage, 0.05 + 0.9 * done); };

  SkeletonStats stats;
  Skeleton skeleton;
  try {
    skeleton = extract_skeleton(cloud, o, &stats);
  } catch (const InputError& e) {
    throw InputError(s.input + ": " + e.what());
  }
  progress("writing " + fs::path(s.output).filename().string(), 0.97);
  io::write_skeleton(s.output, skeleton);
  const double seconds = clock.seconds();
  progress.clear();

  const std::size_t branch_points = count_branch_points(skeleton.graph);
  const std::size_t endpoints = count_endpoints(skeleton.graph);
  if (s.json) {
    nlohmann::ordered_json j;
    j["input"] = s.input;
    j["output"] = s.output;
    j["points"] = cloud.size();
    j["nodes"] = skeleton.node_count();
    j["edges"] = skeleton.edge_count();
    j["branch_points"] = branch_points;
    j["endpoints"] = endpoints;
    j["length"] = total_length(skeleton.graph);
    j["seconds"] = seconds;
    struct rusage usage {};
    ::getrusage(RUSAGE_SELF, &usage);
    j["peak_memory_mb"] = static_cast<double>(usage.ru_maxrss) / 1024.0;
    j["left_out"] = {{"total", skeleton.left_out.total()},
                     {"small_clusters", skeleton.left_out.small_clusters},
                     {"far_parts", skeleton.left_out.far_parts}};
    j["octree_depth"] = stats.octree_depth;
    j["cell_size"] = stats.cell_size;
    j["band_width"] = stats.band_width;
    j["cells"] = stats.cells;
    j["bridges"] = stats.bridges;
    j["parts"] = stats.parts;
    j["level_set_nodes"] = stats.level_set_nodes;
    j["pruned_branches"] = stats.pruned_branches;
    j["refined_splits"] = stats.refined_splits;
    j["forks_moved"] = stats.forks_moved;
    auto& stages = j["stage_seconds"] = nlohmann::ordered_json::object();
    for (const auto& [stage, t] : stats.seconds) stages[stage] = t;
    std::cout << j.dump(2) << '\n';
  } else if (!s.quiet) {
    std::cout << fs::path(s.input).filename().string() << ": " << cloud.size() << " points, " << skeleton.node_count()
              << " nodes, " << branch_points << " branch points, " << endpoints << " endpoints, "
              << format_seconds(seconds);
    if (skeleton.left_out.total() > 0) {
      std::cout << " (left out " << skeleton.left_out.total() << " points:";
      if (skeleton.left_out.small_clusters) std::cout << " " << skeleton.left_out.small_clusters << " in small isolated clusters";
      if (skeleton.left_out.far_parts)
        std::cout << (skeleton.left_out.small_clusters ? "," : "") << " " << skeleton.left_out.far_parts
                  << " in parts beyond the bridging distance";
      std::cout << ")";
    }
    std::cout << " -> " << s.output << '\n';
  }
  return 0;
}

}  // namespace

Command add_skeletonize(CLI::App& app) {
  auto s = std::make_shared<Settings>();
  SkeletonOptions& o = s->options;
  CLI::App* c = app.add_subcommand("skeletonize",
                                   "Extract the curve skeleton of a tree from a point cloud.\n"
                                   "Input: .xyz .txt .asc .csv .pts .ply .las; output by extension: .ply (vertices with radius, "
                                   "edges), .obj (polylines) or .json. Distances are in the cloud's units; 0 picks the "
                                   "default relative to the octree cell size.");
  c->add_option("input", s->input, "Point cloud to skeletonize (default: the bundled example tree)");
  c->add_option("-o,--output", s->output, "Skeleton file to write (default: INPUT_skeleton.ply in this folder)");
  c->add_flag("--json", s->json, "Print a machine-readable JSON report on stdout instead of the summary");
  c->add_flag("-q,--quiet", s->quiet, "Print nothing but errors");

  auto* g = "Method";
  c->add_option("--up", s->up, "Axis the tree grows along: x, y, z, -x, -y, -z or 'x,y,z'")->default_val("z")->group(g);
  c->add_option("--root", s->root, "Point 'x,y,z' (input frame) where the tree stands (default: lowest part of the cloud)")->group(g);
  c->add_option("--root-slice", o.root.slice, "Thickness of the trunk base slice the geodesic distance starts from (0: two cells)")
      ->default_val(o.root.slice)->group(g);
  c->add_option("--depth", o.octree.depth, "Octree depth (0: the deepest whose cells hold --cell-points points on average)")
      ->default_val(o.octree.depth)->check(CLI::Range(0, 21))->group(g);
  c->add_option("--cell-points", o.octree.points_per_cell,
                "Mean points per octree cell that sets the depth (0: the paper's depth, 2 + log8 N)")
      ->default_val(o.octree.points_per_cell)->check(CLI::NonNegativeNumber)->group(g);
  c->add_option("--neighbours", s->neighbours, "Neighbour graph: 'octree' (26-adjacent cells) or 'knn' (k nearest skeleton points)")
      ->default_val("octree")->check(CLI::IsMember({"octree", "knn"}))->group(g);
  c->add_option("--reach", o.graph.reach, "With --neighbours octree: cells this many cells apart are neighbours (1: the paper's 26)")
      ->default_val(o.graph.reach)->check(CLI::Range(1, 3))->group(g);
  c->add_option("-k", o.graph.k, "Neighbours per skeleton point with --neighbours knn")->default_val(o.graph.k)
      ->check(CLI::Range(1, 1000))->group(g);
  c->add_option("--bridge", o.graph.bridge_distance,
                "Join parts of the cloud whose gap is at most this long (0: 4 cells; negative: never)")
      ->default_val(o.graph.bridge_distance)->group(g);
  c->add_option("--small-cluster", o.graph.small_cluster_fraction,
                "Parts left apart that hold less than this share of the points are reported as noise")
      ->default_val(o.graph.small_cluster_fraction)->check(CLI::Range(0.0, 1.0))->group(g);
  c->add_option("--band", o.level_sets.band_width, "Width of a level set band of geodesic distance (0: 2 cells)")
      ->default_val(o.level_sets.band_width)->check(CLI::NonNegativeNumber)->group(g);
  c->add_option("--prune-length", o.prune.min_length, "Remove leaf branches shorter than this (0: 1 band)")
      ->default_val(o.prune.min_length)->check(CLI::NonNegativeNumber)->group(g);
  c->add_option("--prune-radius", o.prune.radius_factor, "... or that stay within this many radii of the branch they leave")
      ->default_val(o.prune.radius_factor)->check(CLI::NonNegativeNumber)->group(g);
  c->add_option("--cpc-weight", o.cpc.weight, "Weight w of the equal-distance (cylinder) term of CPC")
      ->default_val(o.cpc.weight)->check(CLI::NonNegativeNumber)->group(g);
  c->add_option("--eta", o.refine.eta, "Refinement threshold factor eta of eq. 8")->default_val(o.refine.eta)
      ->check(CLI::NonNegativeNumber)->group(g);
  c->add_option("--samples", o.smooth.samples_per_edge, "Spline points inserted between adjacent nodes")
      ->default_val(o.smooth.samples_per_edge)->check(CLI::Range(0, 100))->group(g);
  c->add_option("--tension", o.smooth.tension, "Cardinal spline tension (0: Catmull-Rom, 1: straight)")
      ->default_val(o.smooth.tension)->check(CLI::Range(0.0, 1.0))->group(g);
  c->add_flag("--no-prune", s->no_prune, "Keep every level-set branch, however short")->group(g);
  c->add_flag("--no-cpc", s->no_cpc, "Skip the cylindrical prior constraint (nodes stay at L1-medians)")->group(g);
  c->add_flag("--no-refine", s->no_refine, "Skip the topology refinement at branch nodes")->group(g);
  c->add_flag("--no-junctions", s->no_junctions, "Leave forks where the level sets put them (no axis-meeting placement)")->group(g);
  c->add_flag("--no-smooth", s->no_smooth, "Skip the spline smoothing")->group(g);
  return [s] { return run(*s); };
}

}  // namespace treeskel::cli
