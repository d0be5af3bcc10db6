// treeskel model INPUT -o tree.glb: cloud (or saved skeleton) -> skeleton -> radii -> mesh.
#include "commands.h"
#include "model_options.h"
#include "report.h"
#include "skeleton_options.h"

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

/// Below this share of the skeleton's length inside the mesh, the summary warns.
constexpr double kCoverageWarning = 0.95;
/// Below this share of the wood volume (the frustums of the fitted radii, which the summary reports)
/// in the mesh, the summary warns: the model is much thinner than the measurements. Frustums that
/// overlap (at forks, in crowded crowns) count twice, and the repair thins branches, the trunk too at
/// times; most synthetic trees give 0.78-1.0.
constexpr double kVolumeWarning = 0.7;
/// Sanity warnings: a tree this many times wider than tall, taller than this (the tallest known
/// trees are about 116 m), a DBH over this (the widest trunks are about 11 m across, but a DBH over
/// 3 m is rare enough to check).
constexpr double kUpAxisRatio = 1.5;
constexpr double kTallestTree = 150.0;
constexpr double kWidestTrunk = 3.0;

struct Settings : ModelSettings {
  std::string input;
  std::string output;
  std::string report;
  std::string qsm;
  std::string skeleton_out;
  bool json = false;
  bool quiet = false;
  SkeletonSettings method;
};

/// What looks wrong about the input, from the skeleton's extent and the measurements: an up axis
/// along which the tree is much shorter than across, units that are not metres, a trunk no real
/// tree has.
std::vector<std::string> sanity_warnings(const Skeleton& skeleton, const Eigen::Vector3d& up,
                                         const modeling::TreeMeasurements& m, double breast_height) {
  std::vector<std::string> out;
  Eigen::AlignedBox3d box;
  for (NodeId v = 0; v < skeleton.node_count(); ++v) box.extend(skeleton[v].position);
  if (box.isEmpty()) return out;
  const Eigen::Vector3d size = box.sizes();
  const Eigen::Vector3d u = up.normalized();
  double along = 0.0, across = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double share = std::abs(u[a]);
    along += share * size[a];
    across = std::max(across, (1.0 - share) * size[a]);
  }
  if (across > kUpAxisRatio * along) {
    std::ostringstream w;
    w << "the tree is " << across / along << " times wider than tall along the up axis: if it grows along another "
      << "axis, say so with --up (e.g. --up y)";
    out.push_back(w.str());
  }
  if (m.height > kTallestTree) {
    std::ostringstream w;
    w << "the tree is " << m.height << " units tall: if the units are centimetres or millimetres, the breast height ("
      << breast_height << ") and every default in metres are wrong; convert the cloud or set --breast-height";
    out.push_back(w.str());
  }
  if (m.dbh && *m.dbh > kWidestTrunk) {
    std::ostringstream w;
    w << "a DBH of " << *m.dbh << " is over " << kWidestTrunk << ", rare in any tree: check the units, the up axis, "
      << "or whether this is a tree (an airborne scan of a crown has no trunk to measure)";
    out.push_back(w.str());
  }
  if (!m.dbh && m.height > 0.0 && m.height < breast_height)
    out.push_back("the tree is shorter than breast height, so it has no DBH");
  return out;
}

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
  modeling::check_sweep_options(s.sweep);
  // Every output is checked before any work and committed together at the end: whole or absent.
  io::OutputSet outputs({fs::path(s.input)});
  const fs::path mesh_to = outputs.stage(s.output, "-o");
  const fs::path report_to = s.report.empty() ? fs::path() : outputs.stage(s.report, "--report");
  const fs::path qsm_to = s.qsm.empty() ? fs::path() : outputs.stage(s.qsm, "--qsm");
  const fs::path skeleton_to = s.skeleton_out.empty() ? fs::path() : outputs.stage(s.skeleton_out, "--skeleton");

  Progress progress(s.quiet || s.json);
  progress("reading " + fs::path(s.input).filename().string(), 0.0);
  std::optional<PointCloud> cloud;
  Skeleton skeleton;
  SkeletonStats skeleton_stats;
  const bool from_skeleton = io::looks_like_skeleton(s.input);
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
    if (missing > 0 && !s.quiet && !s.json)
      std::cerr << "note: " << missing << " of " << skeleton.node_count()
                << " nodes have no radius; the pipe model fills them in from the others\n";
  } else {
    cloud = io::read_point_cloud(s.input);
    SkeletonOptions o = skeleton_options_for(s.method, *cloud);
    if (progress.active()) o.progress = [&](const std::string& stage, double done) { progress(stage, 0.05 + 0.6 * done); };
    skeleton = extract_skeleton_of(s.input, *cloud, o, &skeleton_stats);
  }
  const double skeleton_seconds = clock.seconds();

  progress("fitting radii", 0.66);
  modeling::RadiusStats radius_stats;
  try {
    modeling::fit_radii(skeleton, cloud ? &*cloud : nullptr, s.radii, &radius_stats);
  } catch (const InputError& e) {
    throw InputError(s.input + ": " + e.what());
  }
  progress("sweeping the mesh", 0.72);
  modeling::SweepStats sweep_stats;
  modeling::TreeMesh mesh;
  try {
    mesh = modeling::sweep_mesh(skeleton, s.sweep, &sweep_stats);
  } catch (const InputError& e) {
    throw InputError(s.input + ": " + e.what());
  }
  progress("checking the mesh", 0.9);
  modeling::MeshCheck check = modeling::check_mesh(mesh, false);
  check.self_intersections = sweep_stats.self_intersections;
  check.self_intersections_checked = s.sweep.repair;
  // Several closed components (a limb swept apart that its union did not reach) are written with a
  // warning: leaving them out would lose the limbs. Every warning goes to stderr and into the report.
  modeling::MeshCheck as_one = check;
  as_one.components = 1;
  const bool apart_only = !check.ok() && as_one.ok();
  if (!check.ok() && !apart_only && !s.allow_defects)
    throw Error("the mesh of " + s.input + " failed its check: " + check.problem() +
                "; nothing was written (--allow-defects writes it anyway)");
  std::vector<std::string> warnings;
  auto warn = [&](const auto&... parts) {
    std::ostringstream w;
    (w << ... << parts);
    warnings.push_back(w.str());
  };
  if (apart_only)
    warn("the mesh has ", check.components, " closed components: ", check.components - 1,
         " swept-apart limb(s) do not touch the rest; written as they are");
  if (sweep_stats.pieces_failed > 0)
    warn(sweep_stats.pieces_failed, " limb(s)",
         s.sweep.unite_apart ? " could not be united with the tree without the mesh crossing itself (or past the union's budget)"
                             : " found no room at their forks (--no-unite)",
         " and are left out");
  if (sweep_stats.float_crossings > 0)
    warn("rounded to 32-bit floats in the input's frame (as PLY, STL and MeshLab hold it), the mesh crosses itself at ",
         sweep_stats.float_crossings, " face pairs (OBJ keeps full precision; --local writes local coordinates)");
  // How much of the skeleton the mesh holds: a valid mesh can still leave limbs out.
  const modeling::SkeletonCoverage coverage = modeling::skeleton_coverage(skeleton, mesh);
  if (coverage.share() < kCoverageWarning)
    warn("the mesh holds only ", std::lround(100.0 * coverage.share()), "% of the skeleton's length (",
         coverage.inside_length, " of ", coverage.length, ")");
  modeling::MeasureOptions mo;
  mo.up = up;
  mo.breast_height = s.breast_height;
  mo.dbh_from_points = !s.dbh_from_model;
  const modeling::TreeMeasurements measurements = modeling::measure_tree(skeleton, cloud ? &*cloud : nullptr, mo);
  for (auto& w : sanity_warnings(skeleton, up, measurements, s.breast_height)) warnings.push_back(std::move(w));
  if (measurements.volume > 0.0 && check.volume < kVolumeWarning * measurements.volume)
    warn("the mesh's volume is ", std::lround(100.0 * check.volume / measurements.volume),
         "% of the wood volume reported (the frustums of the fitted radii, ", measurements.volume, "; the mesh ",
         check.volume, "): frustums of branches that overlap count twice, and ", sweep_stats.joins_thinned,
         " join(s) and ", sweep_stats.repaired_shrunk,
         " branch(es) with what they carry were thinned to keep the mesh from crossing itself");
  if (!s.json)
    for (const auto& w : warnings) std::cerr << "warning: " << s.input << ": " << w << '\n';

  progress("writing " + fs::path(s.output).filename().string(), 0.95);
  io::MeshFrame frame;
  frame.offset = skeleton.offset;
  frame.up = up;
  frame.local = s.local;
  io::MeshPlacement placed;
  try {
    placed = io::write_mesh(mesh_to, mesh, frame, s.with_skeleton ? &skeleton : nullptr);
  } catch (const Error& e) {
    throw Error(outputs.explain(e.what()));
  }
  if (!placed.note.empty() && !frame.local && !s.quiet)
    std::cerr << "note: " << s.output << " holds " << placed.note << "; add the offset (" << placed.left_out.x() << ", "
              << placed.left_out.y() << ", " << placed.left_out.z() << ") for the input's frame (also in --report)\n";
  try {
    if (!s.qsm.empty()) io::write_qsm_csv(qsm_to, measurements);
    if (!s.skeleton_out.empty()) io::write_skeleton(skeleton_to, skeleton);
  } catch (const Error& e) {
    throw Error(outputs.explain(e.what()));
  }
  const double seconds = clock.seconds();

  nlohmann::ordered_json j;
  j["input"] = s.input;
  j["output"] = s.output;
  if (cloud) j["points"] = cloud->size();
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
                {"exponent", s.radii.exponent}};
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
               {"branches", sweep_stats.branches},
               {"junctions", sweep_stats.junctions},
               {"merged_forks", sweep_stats.merged_forks},
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
               {"pieces_failed", sweep_stats.pieces_failed},
               {"welded_edges", sweep_stats.welded_edges},
               {"float_crossings", sweep_stats.float_crossings}};
  j["frame"] = {{"offset_left_out", {placed.left_out.x(), placed.left_out.y(), placed.left_out.z()}},
                {"y_up_rotation", placed.y_up_rotation},
                {"note", placed.note}};
  j["warnings"] = warnings;
  j["seconds"] = {{"skeleton", skeleton_seconds}, {"total", seconds}};
  j["peak_memory_mb"] = peak_memory_mb();
  write_report_and_commit(outputs, report_to, j);
  progress.clear();
  if (s.json) {
    std::cout << j.dump(2) << '\n';
  } else if (!s.quiet) {
    std::cout << fs::path(s.input).filename().string() << ": ";
    if (cloud) std::cout << cloud->size() << " points, ";
    std::cout << skeleton.node_count() << " nodes, " << check.faces << " triangles ("
              << (!check.ok()              ? check.problem()
                  : s.sweep.repair         ? std::string("closed, manifold, no self-intersection")
                                           : std::string("closed, manifold; self-intersections not checked"))
              << "), " << std::lround(100.0 * coverage.share()) << "% of the skeleton inside, height "
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
  c->add_flag("--json", s->json, "Print the JSON report on stdout instead of the summary");
  c->add_flag("-q,--quiet", s->quiet, "Print nothing but errors");
  add_model_options(*c, *s);
  add_skeleton_options(*c, s->method);
  return [s] { return run(*s); };
}


}  // namespace treeskel::cli
