// treeskel skeletonize INPUT -o OUTPUT
#include "commands.h"
#include "report.h"
#include "skeleton_options.h"
#include "view_options.h"

#include "treeskel/error.h"
#include "treeskel/io/atomic_file.h"
#include "treeskel/io/output_set.h"
#include "treeskel/io/point_cloud_io.h"
#include "treeskel/io/skeleton_io.h"
#include "treeskel/pipeline.h"

#include <nlohmann/json.hpp>

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
  std::string report;
  std::string leaves;
  bool json = false;
  bool quiet = false;
  SkeletonSettings method;
  ViewSettings view;
};

int run(Settings& s) {
  Stopwatch clock;
  if (s.input.empty()) s.input = TREESKEL_DEFAULT_EXAMPLE;
  if (s.output.empty()) s.output = fs::path(s.input).stem().string() + "_skeleton.ply";
  require_skeleton_extension(s.output);
  if (!s.report.empty() && io::extension_of(s.report) != "json") throw OptionError("--report must name a .json file");
  check_skeleton_settings(s.method);
  check_leaves_option(s.method, s.leaves);
  // Every output is checked before any work and committed together at the end: whole or absent.
  io::OutputSet outputs({fs::path(s.input)});
  const fs::path output_to = outputs.stage(s.output, "-o");
  const fs::path report_to = s.report.empty() ? fs::path() : outputs.stage(s.report, "--report");
  const fs::path leaves_to = s.leaves.empty() ? fs::path() : outputs.stage(s.leaves, "--leaves");
  const ViewOutputs view_outputs(s.view, outputs);

  Progress progress(s.quiet || s.json);
  progress("reading " + fs::path(s.input).filename().string(), 0.0);
  PointCloud cloud = io::read_point_cloud(s.input);
  const std::size_t ground = set_ground_aside(s.method, cloud, s.input, s.quiet || s.json);
  Skeleton skeleton;
  SkeletonStats stats;
  const WoodSplit wood = keep_wood_then(s.method, cloud, s.input, s.quiet || s.json, [&] {
    SkeletonOptions o = skeleton_options_for(s.method, cloud);
    if (progress.active()) o.progress = [&](const std::string& stage, double done) { progress(stage, 0.05 + 0.9 * done); };
    skeleton = extract_skeleton_of(s.input, cloud, o, &stats);
  });
  progress("writing " + fs::path(s.output).filename().string(), 0.97);
  try {
    io::write_skeleton(output_to, skeleton);
    if (!s.leaves.empty()) io::write_point_cloud(leaves_to, wood.leaves);
  } catch (const Error& e) {
    throw Error(outputs.explain(e.what()));
  }
  const double seconds = clock.seconds();

  const std::size_t branch_points = count_branch_points(skeleton.graph);
  const std::size_t endpoints = count_endpoints(skeleton.graph);
  nlohmann::ordered_json j;
  j["input"] = s.input;
  j["output"] = s.output;
  j["points"] = cloud.size();
  j["ground_set_aside"] = ground;
  report_wood(wood, j);
  j["nodes"] = skeleton.node_count();
  j["edges"] = skeleton.edge_count();
  j["branch_points"] = branch_points;
  j["endpoints"] = endpoints;
  j["length"] = total_length(skeleton.graph);
  j["seconds"] = seconds;
  j["peak_memory_mb"] = peak_memory_mb();
  j["warnings"] = nlohmann::ordered_json::array();
  if (!wood.leafy_warning.empty()) j["warnings"].push_back(wood.leafy_warning);
  j["left_out"] = {{"total", skeleton.left_out.total()},
                   {"small_clusters", skeleton.left_out.small_clusters},
                   {"far_parts", skeleton.left_out.far_parts},
                   {"outliers", skeleton.left_out.outliers}};
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
  if (view_outputs.wanted()) {
    progress("writing the page", 0.98);
    view::Scene scene;
    scene.title = fs::path(s.input).filename().string();
    scene.cloud = &cloud;
    scene.classes = view::point_classes(cloud, skeleton);
    scene.skeleton = view::skeleton_segments(skeleton);
    scene.up = parse_up(s.method.up);
    scene.report = j;
    view_outputs.write(scene);
  }
  write_report_and_commit(outputs, report_to, j);
  progress.clear();

  if (!s.json && !wood.leafy_warning.empty()) std::cerr << "warning: " << s.input << ": " << wood.leafy_warning << '\n';
  if (s.json) {
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
      if (skeleton.left_out.outliers)
        std::cout << (skeleton.left_out.small_clusters + skeleton.left_out.far_parts ? "," : "") << " "
                  << skeleton.left_out.outliers << " stray far outside the cloud";
      std::cout << ")";
    }
    std::cout << " -> " << s.output << '\n';
  }
  return 0;
}

}  // namespace

Command add_skeletonize(CLI::App& app) {
  auto s = std::make_shared<Settings>();
  CLI::App* c = app.add_subcommand("skeletonize",
                                   "Extract the curve skeleton of a tree from a point cloud.\n"
                                   "Input: .xyz .txt .asc .csv .pts .ply .las .laz; output by extension: .ply (vertices with radius, "
                                   "edges), .obj (polylines) or .json. Distances are in the cloud's units; 0 picks the "
                                   "default relative to the octree cell size.");
  c->add_option("input", s->input, "Point cloud to skeletonize (default: the bundled example tree)");
  c->add_option("-o,--output", s->output, "Skeleton file to write (default: INPUT_skeleton.ply in this folder)");
  c->add_option("--report", s->report, "Also write the JSON report (what --json prints) to this file");
  add_view_options(c, s->view);
  add_leaves_option(*c, s->leaves);
  c->add_flag("--json", s->json, "Print a machine-readable JSON report on stdout instead of the summary");
  c->add_flag("-q,--quiet", s->quiet, "Print nothing but errors");

  add_skeleton_options(*c, s->method);
  return [s] { return run(*s); };
}

}  // namespace treeskel::cli
