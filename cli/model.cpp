// treeskel model INPUT -o tree.glb: cloud (or saved skeleton) -> skeleton -> radii -> mesh.
#include "commands.h"
#include "model_options.h"
#include "model_warnings.h"
#include "report.h"
#include "skeleton_options.h"
#include "view_options.h"

#include "treeskel/error.h"
#include "treeskel/io/atomic_file.h"
#include "treeskel/io/output_set.h"
#include "treeskel/io/mesh_io.h"
#include "treeskel/io/point_cloud_io.h"
#include "treeskel/io/skeleton_io.h"
#include "treeskel/modeling/coverage.h"
#include "treeskel/modeling/measurements.h"
#include "treeskel/modeling/radii.h"
#include "treeskel/modeling/sweep.h"

#include <nlohmann/json.hpp>
#include <tbb/parallel_invoke.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <vector>

namespace treeskel::cli {

namespace {

namespace fs = std::filesystem;

struct Settings : ModelSettings {
  std::string input;
  std::string output;
  std::string report;
  std::string qsm;
  std::string skeleton_out;
  std::string leaves;
  bool json = false;
  bool quiet = false;
  SkeletonSettings method;
  ViewSettings view;
};

int run(Settings& s) {
  Stopwatch clock;
  if (s.input.empty()) s.input = TREESKEL_DEFAULT_EXAMPLE;
  if (s.output.empty()) s.output = fs::path(s.input).stem().string() + "_model.glb";
  if (!io::is_mesh_extension(s.output))
    throw OptionError(s.output + ": unknown mesh extension '." + io::extension_of(s.output) +
                      "'; use .obj, .gltf, .glb, .ply or .stl");
  if (!s.report.empty() && io::extension_of(s.report) != "json") throw OptionError("--report must name a .json file");
  if (!s.qsm.empty() && io::extension_of(s.qsm) != "csv") throw OptionError("--qsm must name a .csv file");
  if (!s.skeleton_out.empty()) require_skeleton_extension(s.skeleton_out);
  check_skeleton_settings(s.method);
  check_leaves_option(s.method, s.leaves);
  modeling::check_sweep_options(s.sweep);
  // Every output is checked before any work and committed together at the end: whole or absent.
  io::OutputSet outputs({fs::path(s.input)});
  const fs::path mesh_to = outputs.stage(s.output, "-o");
  const fs::path report_to = s.report.empty() ? fs::path() : outputs.stage(s.report, "--report");
  const fs::path qsm_to = s.qsm.empty() ? fs::path() : outputs.stage(s.qsm, "--qsm");
  const fs::path skeleton_to = s.skeleton_out.empty() ? fs::path() : outputs.stage(s.skeleton_out, "--skeleton");
  const fs::path leaves_to = s.leaves.empty() ? fs::path() : outputs.stage(s.leaves, "--leaves");
  const ViewOutputs view_outputs(s.view, outputs);

  Progress progress(s.quiet || s.json);
  progress("reading " + fs::path(s.input).filename().string(), 0.0);
  std::optional<PointCloud> cloud;
  Skeleton skeleton;
  SkeletonStats skeleton_stats;
  WoodSplit wood;
  std::size_t ground = 0;
  const bool from_skeleton = io::looks_like_skeleton(s.input);
  if (from_skeleton && may_set_leaves_aside(s.method))
    throw OptionError(std::string(leaves_option(s.method)) + " sets leaves aside from a point cloud; " + s.input +
                      " is a skeleton");
  Eigen::Vector3d up = parse_up(s.method.up);
  if (from_skeleton) {
    skeleton = io::read_skeleton(s.input);
    recentre_offset(skeleton);  // swept in small numbers, written back in the input's frame
    // A skeleton saved by `skeletonize` has radii only where the method measured them (0 elsewhere):
    // the pipe model fills in the rest from the positive ones when the radii are fitted below.
    std::size_t missing = 0;
    for (NodeId v = 0; v < skeleton.node_count(); ++v) {
      if (!std::isfinite(skeleton[v].radius) || skeleton[v].radius < 0.0)
        throw InputError(s.input + ": node " + std::to_string(v) + " has radius " + std::to_string(skeleton[v].radius) +
                         "; radii must be finite and not negative (0: to be filled by the pipe model)");
      if (skeleton[v].radius == 0.0) ++missing;
    }
    if (!s.quiet && !s.json) {
      if (missing > 0)
        std::cerr << "note: " << missing << " of " << skeleton.node_count()
                  << " nodes have no radius; the pipe model fills them in from the others\n";
      // The level sets' radii are mean distances to a node, not circles fitted to the bark: on
      // AdTree's samples the wood volume came out at 0.13-0.76 of the cloud's own model's.
      std::cerr << "note: the radii are the skeleton file's (from `skeletonize`: the level sets' estimates); "
                   "`model CLOUD --skeleton FILE` saves a skeleton with radii fitted to the points (docs/models.md, "
                   "\"Other ways in\")\n";
    }
  } else {
    cloud = io::read_point_cloud(s.input);
    ground = set_ground_aside(s.method, *cloud, s.input, s.quiet || s.json);
    wood = keep_wood_then(s.method, *cloud, s.input, s.quiet || s.json, [&] {
      SkeletonOptions o = skeleton_options_for(s.method, *cloud);
      if (progress.active()) o.progress = [&](const std::string& stage, double done) { progress(stage, 0.05 + 0.6 * done); };
      skeleton = extract_skeleton_of(s.input, *cloud, o, &skeleton_stats);
    });
  }
  const double skeleton_seconds = clock.seconds();

  progress("fitting radii", 0.66);
  modeling::RadiusStats radius_stats;
  try {
    modeling::RadiusOptions radii = s.radii;
    radii.cell_size = skeleton_stats.cell_size;
    if (!cloud && radii.complete && !s.quiet && !s.json)
      std::cerr << "note: --complete needs the cloud's points; a saved skeleton is modelled as it is\n";
    modeling::fit_radii(skeleton, cloud ? &*cloud : nullptr, radii, &radius_stats);
  } catch (const InputError& e) {
    throw InputError(s.input + ": " + e.what());
  }
  const double radii_done = clock.seconds();
  progress("sweeping the mesh", 0.72);
  modeling::SweepStats sweep_stats;
  modeling::TreeMesh mesh;
  try {
    modeling::SweepOptions sweep = s.sweep;
    sweep.local_floats = s.local || io::holds_local_floats(mesh_to);
    mesh = modeling::sweep_mesh(skeleton, sweep, &sweep_stats);
  } catch (const InputError& e) {
    throw InputError(s.input + ": " + e.what());
  }
  const double mesh_done = clock.seconds();
  progress("checking the mesh", 0.9);
  // The share of the skeleton and of its wood inside (mostly one core's work: an AABB tree of the
  // mesh, then the samples) runs beside the checks, the measurements and the writing of the mesh, which
  // need nothing from it; the warnings wait for both. (One after the other, the share took 0.3 s of
  // AdTree's Lille_2 and 0.5 s of its Paris_Luxembourg_1.)
  modeling::MeshCheck check;
  modeling::SkeletonCoverage coverage;
  std::optional<modeling::TreeMeasurements> measured;
  io::MeshFrame frame;
  frame.offset = skeleton.offset;
  frame.up = up;
  frame.local = s.local;
  io::MeshPlacement placed;
  double checks_done = 0.0;
  tbb::parallel_invoke(
      [&] { coverage = modeling::skeleton_coverage(skeleton, mesh); },
      [&] {
        check = check_swept(mesh, sweep_stats, s.sweep.repair);
        checks_done = clock.seconds();
        // Several closed components (a limb swept apart that its union did not reach) are written
        // with a warning: leaving them out would lose the limbs.
        if (!check.ok() && !only_apart(check) && !s.allow_defects)
          throw Error("the mesh of " + s.input + " failed its check: " + check.problem() +
                      "; nothing was written (--allow-defects writes it anyway)");
        modeling::MeasureOptions mo;
        mo.up = up;
        mo.breast_height = s.breast_height;
        mo.dbh_from_points = !s.dbh_from_model;
        measured = modeling::measure_tree(skeleton, cloud ? &*cloud : nullptr, mo);
        progress("writing " + fs::path(s.output).filename().string(), 0.95);
        try {
          placed = io::write_mesh(mesh_to, mesh, frame, s.with_skeleton ? &skeleton : nullptr);
        } catch (const Error& e) {
          throw Error(outputs.explain(e.what()));
        }
      });
  const modeling::TreeMeasurements& measurements = *measured;
  // Every warning goes to stderr and into the report.
  std::vector<std::string> warnings =
      model_warnings({skeleton, up, measurements, s.breast_height, check, sweep_stats, coverage, s.sweep.unite_apart});
  if (!wood.leafy_warning.empty()) warnings.insert(warnings.begin(), wood.leafy_warning);
  if (cloud)
    if (std::string w = bushes_left_out(radius_stats.completion, cloud->size()); !w.empty()) warnings.push_back(std::move(w));
  if (!s.json)
    for (const auto& w : warnings) std::cerr << "warning: " << s.input << ": " << w << '\n';
  if (!placed.note.empty() && !frame.local && !s.quiet)
    std::cerr << "note: " << s.output << " holds " << placed.note << "; add the offset (" << placed.left_out.x() << ", "
              << placed.left_out.y() << ", " << placed.left_out.z() << ") for the input's frame (also in --report)\n";
  try {
    if (!s.qsm.empty()) io::write_qsm_csv(qsm_to, measurements);
    if (!s.skeleton_out.empty()) io::write_skeleton(skeleton_to, skeleton);
    if (!s.leaves.empty()) io::write_point_cloud(leaves_to, wood.leaves);
  } catch (const Error& e) {
    throw Error(outputs.explain(e.what()));
  }
  const double seconds = clock.seconds();

  nlohmann::ordered_json j;
  j["input"] = s.input;
  j["output"] = s.output;
  if (cloud) j["points"] = cloud->size();
  if (cloud) j["ground_set_aside"] = ground;
  report_wood(wood, j);
  j["nodes"] = skeleton.node_count();
  j["branch_points"] = count_branch_points(skeleton.graph);
  j["endpoints"] = count_endpoints(skeleton.graph);
  j["measurements"] = measurements_json(measurements);
  j["left_out"] = {{"total", skeleton.left_out.total()},
                   {"small_clusters", skeleton.left_out.small_clusters},
                   {"far_parts", skeleton.left_out.far_parts},
                   {"outliers", skeleton.left_out.outliers}};
  j["radii"] = {{"measured_nodes", radius_stats.measured},
                {"reliable_nodes", radius_stats.reliable},
                {"from_stored_radii", radius_stats.used_stored},
                {"exponent", s.radii.exponent},
                {"stem_share_bound", s.radii.max_share_over_pipe},
                {"stub_length", s.radii.stub_length},
                {"fork_margin", s.radii.fork_margin},
                {"stubs", radius_stats.stubs},
                {"base_lowered", radius_stats.base_lowered},
                {"stiffness", s.radii.stiffness},
                {"straightened_limbs", radius_stats.straightened.limbs},
                {"straightened_nodes", radius_stats.straightened.moved},
                {"largest_shift", radius_stats.straightened.largest_shift},
                {"largest_shift_radii", radius_stats.straightened.largest_shift_radii}};
  const CompleteStats& grafted = radius_stats.completion;
  j["completion"] = {{"run", s.radii.complete && cloud.has_value()},
                     {"tufts_and_bushes", s.radii.complete && cloud.has_value() && s.radii.completion.tufts_and_bushes},
                     {"uncovered_points", grafted.uncovered_points},
                     {"grafted_points", grafted.grafted_points},
                     {"branches", grafted.branches},
                     {"nodes", grafted.nodes},
                     {"bushy_grafts", grafted.bushy_grafts},
                     {"bushy_points", grafted.bushy_points},
                     {"leafy_bushes", grafted.leafy_bushes}};
  j["mesh"] = {{"vertices", check.vertices},
               {"triangles", check.faces},
               {"closed", check.boundary_edges == 0},
               {"manifold", check.non_manifold_vertices == 0},
               {"components", check.components},
               {"self_intersections", s.sweep.repair ? nlohmann::ordered_json(check.self_intersections) : nlohmann::ordered_json(nullptr)},
               {"volume", check.volume},
               {"area", check.area},
               {"skeleton_coverage", coverage.share()},
               {"skeleton_length", coverage.length},
               {"skeleton_length_inside", coverage.inside_length},
               {"wood_inside", coverage.wood.share()},
               {"branches", sweep_stats.branches},
               {"junctions", sweep_stats.junctions},
               {"merged_forks", sweep_stats.merged_forks},
               {"straightened_branches", sweep_stats.straightened_branches},
               {"thin_left_out", sweep_stats.thin_left_out},
               {"relocated_branches", sweep_stats.relocated_branches},
               {"twigs_absorbed", sweep_stats.twigs_absorbed},
               {"joins_thinned", sweep_stats.joins_thinned},
               {"joins_dropped", sweep_stats.joins_dropped},
               {"repaired_shrunk", sweep_stats.repaired_shrunk},
               {"repaired_dropped", sweep_stats.repaired_dropped},
               {"raised_to_floor", sweep_stats.raised_to_floor},
               {"pieces_united", sweep_stats.pieces},
               {"unions", sweep_stats.unions},
               {"pieces_apart", sweep_stats.pieces_apart},
               {"pieces_nudged", sweep_stats.pieces_nudged},
               {"pieces_failed", sweep_stats.pieces_failed},
               {"welded_edges", sweep_stats.welded_edges},
               {"voids_filled", sweep_stats.voids_filled},
               {"float_crossings", sweep_stats.float_crossings}};
  j["frame"] = {{"offset_left_out", {placed.left_out.x(), placed.left_out.y(), placed.left_out.z()}},
                {"y_up_rotation", placed.y_up_rotation},
                {"note", placed.note}};
  j["warnings"] = warnings;
  // Where the time went: reading and the skeleton, the radii, the mesh (sweep and unions), its
  // checks, then measurements and writing (the share of the skeleton inside runs beside those two
  // and counts with the second as far as it outlasts them); they add up to total.
  j["seconds"] = {{"skeleton", skeleton_seconds},
                  {"radii", radii_done - skeleton_seconds},
                  {"mesh", mesh_done - radii_done},
                  {"checks", checks_done - mesh_done},
                  {"measure_and_write", seconds - checks_done},
                  {"total", seconds}};
  // The mesh's own stages (modeling::SweepStats): the tree's sweep with its repair rounds, of which
  // CGAL's whole-mesh tests, then the pieces' sweeps and their unions with the tree; `mesh` above
  // is their sum and what little comes between them.
  j["mesh_seconds"] = {{"sweep", sweep_stats.sweep_seconds},
                       {"whole_mesh_tests", sweep_stats.test_seconds},
                       {"pieces", sweep_stats.pieces_seconds},
                       {"unions", sweep_stats.union_seconds}};
  j["peak_memory_mb"] = peak_memory_mb();
  if (view_outputs.wanted()) {
    progress("writing the page", 0.97);
    view::Scene scene;
    scene.title = fs::path(s.input).filename().string();
    if (cloud) {
      scene.cloud = &*cloud;
      scene.classes = view::point_classes(*cloud, skeleton);
    }
    for (const auto& c : measurements.cylinders)
      scene.skeleton.push_back({c.start, c.start + c.axis * c.length, c.order, c.radius});
    scene.mesh = &mesh;
    scene.mesh_offset = skeleton.offset;
    scene.up = up;
    scene.report = j;
    view_outputs.write(scene);
  }
  write_report_and_commit(outputs, report_to, j);
  progress.clear();
  if (s.json) {
    std::cout << j.dump(2) << '\n';
  } else if (!s.quiet) {
    std::cout << fs::path(s.input).filename().string() << ": ";
    if (cloud) std::cout << cloud->size() << " points, ";
    std::cout << skeleton.node_count() << " nodes, ";
    if (grafted.nodes > 0)
      std::cout << grafted.branches << " branches grown through " << grafted.grafted_points << " points it passed by"
                << (grafted.bushy_grafts > 0 ? " (not through " + std::to_string(grafted.bushy_points) + " in " +
                                                   std::to_string(grafted.bushy_grafts) + " bushes)"
                                             : std::string())
                << ", ";
    std::cout << check.faces << " triangles ("
              << (!check.ok()              ? check.problem()
                  : s.sweep.repair         ? std::string("closed, manifold, no self-intersection")
                                           : std::string("closed, manifold; self-intersections not checked"))
              << "), " << std::lround(100.0 * coverage.share()) << "% of the skeleton inside ("
              << std::lround(100.0 * coverage.wood.share()) << "% of its wood), height "
              << measurements.height << ", DBH ";
    if (measurements.dbh)
      std::cout << *measurements.dbh << modeling::dbh_note(measurements);
    else std::cout << "n/a (shorter than " << s.breast_height << ")";
    std::cout << ", wood volume " << measurements.volume << ", " << format_seconds(seconds) << " -> " << s.output << '\n';
  }
  return 0;
}

}  // namespace

Command add_model(CLI::App& app) {
  auto s = std::make_shared<Settings>();
  CLI::App* c = app.add_subcommand(
      "model",
      "Turn a tree point cloud (or a saved skeleton) into one watertight mesh: skeleton, radii by the pipe model "
      "(Leonardo's rule), branches swept and joined at forks.\n"
      "Output by extension: .glb .gltf (glTF 2.0), .obj, .ply, .stl. Distances are in the input's units.");
  c->add_option("input", s->input,
                "Point cloud (.xyz .txt .asc .csv .pts .ply .las .laz) or skeleton (.json, or .ply with edges) "
                "(default: the bundled example tree)");
  c->add_option("-o,--output", s->output, "Mesh file to write (default: INPUT_model.glb in this folder)");
  c->add_option("--report", s->report, "Also write the measurements and mesh checks as JSON to this file");
  c->add_option("--qsm", s->qsm, "Also write the cylinder table (QSM columns) as CSV to this file");
  c->add_option("--skeleton", s->skeleton_out, "Also write the skeleton with its fitted radii (.ply, .obj or .json)");
  add_view_options(c, s->view);
  add_leaves_option(*c, s->leaves);
  c->add_flag("--json", s->json, "Print the JSON report on stdout instead of the summary");
  c->add_flag("-q,--quiet", s->quiet, "Print nothing but errors");
  add_model_options(*c, *s);
  use_model_defaults(s->method);
  add_skeleton_options(*c, s->method);
  return [s] { return run(*s); };
}


}  // namespace treeskel::cli
