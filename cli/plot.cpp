// treeskel plot INPUT -o OUTDIR: a plot scan -> ground, stems, one cloud per tree -> one model per
// tree by the batch runner (each tree a process of its own) -> trees.csv, trees.json, plan.png.
#include "batch.h"
#include "commands.h"
#include "report.h"
#include "view_options.h"

#include "treeskel/error.h"
#include "treeskel/forest/ground.h"
#include "treeskel/forest/segment.h"
#include "treeskel/forest/stems.h"
#include "treeskel/io/atomic_file.h"
#include "treeskel/io/mesh_io.h"
#include "treeskel/io/point_cloud_io.h"
#include "treeskel/view/plan.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <regex>
#include <set>
#include <memory>
#include <sstream>

namespace treeskel::cli {

namespace {

namespace fs = std::filesystem;

struct Settings {
  std::string input;
  bool segment_only = false;
  bool ground_filter = false;  // find the ground by the filter even when the file classifies it
  bool keep_leaves = false;    // model each tree whole, leafy or not (else --wood-if-leafy for each)
  std::size_t min_tree_points = 500;
  std::string stem_slice;  // "LOW,HIGH"
  std::string labelled = "ply";  // the labelled cloud's format: ply or las
  forest::GroundOptions ground;
  forest::StemOptions stems;
  forest::SegmentOptions segment;
  BatchSettings batch;
};

/// The class of a point in the labelled cloud.
enum : std::uint8_t { kNoTree = 0, kGround = 1, kTree = 2 };

void parse_slice(const std::string& text, forest::StemOptions& stems) {
  if (text.empty()) return;
  std::istringstream in(text);
  char comma = 0;
  double low = 0, high = 0;
  if (!(in >> low >> comma >> high) || comma != ',' || !(in >> std::ws).eof() || !(high > low) || low < 0)
    throw OptionError("--stem-slice " + text + ": give LOW,HIGH heights above the ground, LOW < HIGH, e.g. 0.3,1.8");
  stems.slice_bottom = low;
  stems.slice_top = high;
}

std::string tree_name(std::size_t id, std::size_t count) {
  std::ostringstream out;
  out << "tree_" << std::setw(std::max<int>(3, static_cast<int>(std::to_string(count).size()))) << std::setfill('0') << id;
  return out.str();
}

/// `v` to the millimetre (the nearest double to a decimal of three places, so the files read "3.55").
double rounded(double v) { return std::round(v * 1000.0) / 1000.0; }

int run(Settings& s) {
  Stopwatch clock;
  parse_slice(s.stem_slice, s.stems);
  BatchSettings& b = s.batch;
  if (b.model.empty() && b.skeleton.empty()) b.model = "glb";
  if (!b.model.empty() && !io::is_mesh_extension("x." + b.model))
    throw OptionError("--model " + b.model + ": unknown mesh format; use obj, gltf, glb, ply or stl");
  if (!b.skeleton.empty()) require_skeleton_extension("x." + b.skeleton);
  if (b.model == "ply") b.model_suffix = "_mesh";  // tree_NNN.ply is the tree's cloud
  check_skeleton_settings(b.method);
  if (s.keep_leaves && may_set_leaves_aside(b.method))
    throw OptionError(std::string("--keep-leaves and ") + leaves_option(b.method) + ": give one");
  if (!s.keep_leaves && !may_set_leaves_aside(b.method)) {  // the default: leaves set aside from each leafy tree
    b.method.wood_if_leafy = true;
    b.defaults.push_back("--wood-if-leafy");
  }
  if (b.preview) require_chromium_for_preview();
  if (s.labelled != "ply" && s.labelled != "las")
    throw OptionError("--labelled " + s.labelled + ": the labelled cloud is written as ply or las");
  const fs::path out_dir(b.out_dir);
  std::error_code ec;
  fs::create_directories(out_dir / "trees", ec);
  if (!fs::is_directory(out_dir / "trees"))
    throw OptionError("-o " + b.out_dir + ": cannot make this folder: " + ec.message());
  auto say = [&](const std::string& line) {
    if (!b.quiet) std::cerr << line << std::endl;
  };

  say("reading " + s.input);
  const PointCloud cloud = io::read_point_cloud(s.input);
  Stopwatch stage;
  // A LAS file's classification, when it has ground (class 2), is the ground; --ground-filter ignores it.
  const bool use_classes = !s.ground_filter && std::count(cloud.classes.begin(), cloud.classes.end(), std::uint8_t{2}) > 0;
  if (use_classes) say("the ground: the file's classification (class 2); --ground-filter finds it by the filter instead");
  const forest::Ground ground = forest::classify_ground(cloud, s.ground, use_classes ? &cloud.classes : nullptr);
  const double ground_seconds = stage.seconds();
  stage = Stopwatch();
  const std::vector<forest::Stem> stems = forest::find_stems(cloud, ground, s.stems);
  const double stem_seconds = stage.seconds();
  stage = Stopwatch();
  const forest::Segmentation seg = forest::segment_trees(cloud, ground, stems, s.stems, s.segment);
  const std::vector<forest::TreeShape> shapes = forest::describe_trees(cloud, stems, seg, s.stems);
  const double segment_seconds = stage.seconds();
  const std::size_t in_trees = cloud.size() - ground.ground_points - seg.unassigned_points + seg.stem_base_points;
  auto share = [&](std::size_t n) {
    std::ostringstream out;
    out << n << " (" << std::fixed << std::setprecision(1) << 100.0 * static_cast<double>(n) / static_cast<double>(cloud.size()) << "%)";
    return out.str();
  };
  say(std::to_string(cloud.size()) + " points: ground " + share(ground.ground_points - seg.stem_base_points) + ", in " +
      std::to_string(stems.size()) + " trees " + share(in_trees) + ", in no tree " + share(seg.unassigned_points) +
      "; ground " + format_seconds(ground_seconds) + ", stems " + format_seconds(stem_seconds) + ", trees " +
      format_seconds(segment_seconds));
  const double top = bounding_box(cloud).max().z() - ground.terrain.elevation(bounding_box(cloud).center().x(), bounding_box(cloud).center().y());
  if (top > 150 || top < 2)
    std::cerr << "warning: the plot stands " << top << " units above its ground: treeskel plot works in metres "
              << "(its slice, voxel and gap sizes are metres); scale the cloud to metres first\n";

  // The labelled cloud: every point with its tree, class and height above the ground.
  io::CloudWriteOptions labelled;
  labelled.fields = {{"tree_id", io::PointField::Type::uint32, {}},
                     {"class", io::PointField::Type::uint8, {}},
                     {"height", io::PointField::Type::float32, {}}};
  for (auto& f : labelled.fields) f.values.resize(cloud.size());
  for (std::size_t p = 0; p < cloud.size(); ++p) {
    labelled.fields[0].values[p] = seg.tree[p];
    labelled.fields[1].values[p] = seg.tree[p] ? kTree : ground.is_ground[p] ? kGround : kNoTree;
    labelled.fields[2].values[p] = ground.height[p];
  }
  const std::string labelled_name = "labelled." + s.labelled;
  PointCloud classified;
  if (s.labelled == "las" && cloud.classes.empty()) {
    // LAS's own classification too, where the file had none: 2 ground, 5 high vegetation (a tree),
    // 1 unclassified. A classification the input had is kept as it was.
    classified = cloud;
    classified.classes.resize(cloud.size());
    for (std::size_t p = 0; p < cloud.size(); ++p)
      classified.classes[p] = seg.tree[p] ? 5 : ground.is_ground[p] ? 2 : 1;
  }
  io::write_point_cloud(out_dir / labelled_name, classified.empty() ? cloud : classified, labelled);
  fs::remove(out_dir / (s.labelled == "las" ? "labelled.ply" : "labelled.las"), ec);  // an earlier run's, in the other format

  // One cloud per tree, in the input's frame.
  std::vector<PointCloud> trees(stems.size());
  for (auto& t : trees) t.offset = cloud.offset;
  for (std::size_t p = 0; p < cloud.size(); ++p) {
    if (!seg.tree[p]) continue;
    append_point(trees[seg.tree[p] - 1], cloud, p);
  }
  std::vector<std::string> names(stems.size());
  for (std::size_t t = 0; t < stems.size(); ++t) names[t] = tree_name(t + 1, stems.size());
  // What an earlier run left in trees/ that this one does not make again: the files of trees it no
  // longer finds, and the outputs of a tree whose cloud changed (other options, another input), which
  // --resume would otherwise keep as done.
  const std::set<std::string> current(names.begin(), names.end());
  std::set<std::string> changed;
  std::vector<std::string> modelled;
  for (std::size_t t = 0; t < stems.size(); ++t) {
    const fs::path file = out_dir / "trees" / (names[t] + ".ply");
    const std::string before = fs::is_regular_file(file, ec) ? io::read_whole_file(file) : std::string();
    if (trees[t].empty()) {
      changed.insert(names[t]);
      fs::remove(file, ec);
      continue;
    }
    io::write_point_cloud(file, trees[t]);
    if (before != io::read_whole_file(file)) changed.insert(names[t]);
    if (trees[t].size() >= s.min_tree_points) modelled.push_back(file.string());
  }
  static const std::regex made_by_plot(R"((tree_[0-9]+)(_report\.json|_skeleton\.[a-z]+|_leaves\.ply|_mesh\.ply|\.[a-z]+))");
  for (const auto& entry : fs::directory_iterator(out_dir / "trees", ec)) {
    std::smatch m;
    const std::string file = entry.path().filename().string();
    if (!std::regex_match(file, m, made_by_plot)) continue;
    const bool gone = !current.count(m[1].str());
    const bool stale = changed.count(m[1].str()) && m[2].str() != ".ply";
    const bool leaves_kept = !s.segment_only && !may_set_leaves_aside(b.method) && m[2].str() == "_leaves.ply";
    if (gone || stale || leaves_kept) fs::remove(entry.path(), ec);
  }
  std::vector<view::PlanLabel> labels;
  for (std::size_t t = 0; t < stems.size(); ++t) labels.push_back({stems[t].centre, std::to_string(t + 1)});
  view::write_png(out_dir / "plan.png", view::plan_view(cloud, seg.tree, ground.is_ground, labels));

  // The models, by the batch runner: a process per tree, failures isolated.
  std::map<std::string, BatchRow> rows;
  int batch_code = 0;
  if (!s.segment_only && !modelled.empty()) {
    say("modelling " + std::to_string(modelled.size()) + " trees into " + (out_dir / "trees").string());
    b.inputs = modelled;
    const std::string plot_dir = b.out_dir;
    b.out_dir = (out_dir / "trees").string();
    std::vector<BatchRow> finished;
    batch_code = run_batch(b, &finished);
    b.out_dir = plot_dir;
    for (auto& r : finished) rows[r.input.name.string()] = std::move(r);
  }

  // trees.csv and trees.json: one row per stem.
  const std::vector<std::string> columns{"id", "name", "x", "y", "ground_z", "points", "leaf_points", "height", "crown_base", "stem_dbh",
                                         "dbh", "volume", "skeleton_coverage", "status", "warnings", "model", "error"};
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  std::size_t ok = 0, from_wood = 0;
  for (std::size_t t = 0; t < stems.size(); ++t) {
    const forest::Stem& st = stems[t];
    const forest::TreeShape& sh = shapes[t];
    nlohmann::ordered_json j;
    j["id"] = t + 1;
    j["name"] = names[t];
    j["x"] = rounded(st.centre.x() + cloud.offset.x());
    j["y"] = rounded(st.centre.y() + cloud.offset.y());
    j["ground_z"] = rounded(st.ground + cloud.offset.z());
    j["points"] = sh.points;
    j["leaf_points"] = nullptr;
    j["height"] = rounded(sh.height);
    j["crown_base"] = rounded(sh.crown_base);
    j["stem_dbh"] = rounded(2 * st.radius);
    j["dbh"] = nullptr;
    j["volume"] = nullptr;
    j["skeleton_coverage"] = nullptr;
    j["warnings"] = nlohmann::ordered_json::array();
    j["model"] = nullptr;
    j["error"] = nullptr;
    const auto it = rows.find(names[t]);
    if (it == rows.end()) {
      j["status"] = s.segment_only ? "segmented" : "not modelled";
      if (!s.segment_only)
        j["error"] = "its " + std::to_string(sh.points) + " points are fewer than --min-tree-points " +
                     std::to_string(s.min_tree_points);
    } else {
      const BatchRow& r = it->second;
      const nlohmann::json& f = r.facts;
      using P = nlohmann::json::json_pointer;
      auto fact = [&](const char* at) {
        return f.is_object() && f.contains(P(at)) ? nlohmann::ordered_json(f.at(P(at))) : nlohmann::ordered_json(nullptr);
      };
      j["leaf_points"] = leaf_points_of(f);
      if (j["leaf_points"].is_null() && f.is_object() && f.contains("points")) j["leaf_points"] = 0;  // --keep-leaves
      j["dbh"] = fact("/measurements/dbh");
      j["volume"] = fact("/measurements/volume");
      j["skeleton_coverage"] = fact("/mesh/skeleton_coverage");
      j["status"] = r.status;
      if (f.is_object() && f.contains("warnings")) j["warnings"] = f["warnings"];
      if (r.status == "ok" && !r.outputs.empty()) j["model"] = fs::relative(r.outputs.front(), out_dir).generic_string();
      if (!r.error.empty()) j["error"] = r.error;
      ok += r.status == "ok";
      from_wood += r.status == "ok" && j["leaf_points"].is_number() && j["leaf_points"].get<std::size_t>() > 0;
    }
    list.push_back(j);
  }
  io::write_atomically(out_dir / "trees.csv", [&](std::ostream& out) {
    for (std::size_t c = 0; c < columns.size(); ++c) out << (c ? "," : "") << columns[c];
    out << '\n';
    for (const auto& j : list) {
      for (std::size_t c = 0; c < columns.size(); ++c) {
        const auto& v = j[columns[c]];
        out << (c ? "," : "") << csv_field(csv_text(v));
      }
      out << '\n';
    }
  });
  nlohmann::ordered_json doc;
  doc["treeskel"] = TREESKEL_VERSION;
  doc["input"] = s.input;
  doc["points"] = cloud.size();
  doc["ground_points"] = ground.ground_points - seg.stem_base_points;
  doc["tree_points"] = in_trees;
  doc["unassigned_points"] = seg.unassigned_points;
  doc["seconds"] = {{"ground", ground_seconds}, {"stems", stem_seconds}, {"trees", segment_seconds}, {"total", clock.seconds()}};
  doc["outputs"] = {{"labelled", labelled_name}, {"plan", "plan.png"}, {"trees", "trees/"}};
  doc["trees"] = list;
  io::write_atomically(out_dir / "trees.json", [&](std::ostream& out) { out << doc.dump(2) << '\n'; });

  std::size_t failed = 0;
  for (const auto& [name, row] : rows) failed += row.status == "failed";
  std::ostringstream line;
  line << stems.size() << " trees";
  if (!s.segment_only) line << ", " << ok << " modelled" << (failed ? ", " + std::to_string(failed) + " failed" : "");
  if (from_wood > 0)
    line << " (" << from_wood << " of them from their wood alone: they looked leafy, and their leaves are in "
         << "trees/tree_NNN_leaves.ply and counted in leaf_points; --keep-leaves models them whole)";
  line << ", " << format_duration(clock.seconds()) << "; table in " << (out_dir / "trees.csv").string()
       << ", picture in " << (out_dir / "plan.png").string();
  (failed ? std::cerr : std::cout) << line.str() << '\n';
  if (stems.empty()) {
    std::cerr << "treeskel: error: no stem found in the slice " << s.stems.slice_bottom << " to " << s.stems.slice_top
              << " above the ground (a trunk of radius " << s.stems.min_radius << " to " << s.stems.max_radius
              << " with points in " << s.stems.min_layers << " of its " << s.stems.layers
              << " layers); see plan.png, and --stem-slice\n";
    return 1;
  }
  return batch_code;
}

}  // namespace

Command add_plot(CLI::App& app) {
  auto s = std::make_shared<Settings>();
  CLI::App* c = app.add_subcommand(
      "plot",
      "A plot scan to one model per tree: finds the ground (the file's class 2 when a LAS file has one, else a progressive morphological filter) and the stems "
      "(circles in a slice above the ground), gives every other point to the stem nearest along a voxel graph, "
      "and models each tree by the batch runner (a process per tree). A tree whose points look leafy (16% or more "
      "look like leaves or needles) is modelled from its wood, its leaves set aside (--wood-if-leafy; --keep-leaves "
      "models every tree whole, --wood-only sets leaves aside from every tree). The cloud must be z-up and in metres.\n"
      "Writes OUTDIR/labelled.ply or .las (every point with tree_id, 0 for none; class: 0 no tree, 1 ground, 2 tree; "
      "height above the ground), OUTDIR/trees/tree_NNN.ply (each tree's points) with tree_NNN.glb and "
      "tree_NNN_report.json and tree_NNN_leaves.ply (the points set aside as leaves; none when the tree did not look "
      "leafy) beside, OUTDIR/trees.csv and trees.json (id, stem position in the input's frame, "
      "ground elevation, points, points set aside as leaves, height, crown base, stem DBH from the slice, model DBH, volume, coverage, "
      "status, the model's warnings) and OUTDIR/plan.png (the plot from above, a colour and the id per tree). Exit code 0 when every "
      "tree with --min-tree-points or more points modelled, 1 when any failed or no stem was found.");
  c->add_option("input", s->input, "The plot's cloud (.xyz .txt .csv .ply .las .laz ...)")->required();
  c->add_option("-o,--output", s->batch.out_dir, "Folder to write into (made if missing)")->required();
  c->add_option("--model", s->batch.model, "Mesh format of each tree's model: glb (the default), gltf, obj, ply (written as tree_NNN_mesh.ply, beside the tree's cloud tree_NNN.ply) or stl");
  c->add_option("--skeleton", s->batch.skeleton, "Also write each tree's skeleton in this format: json, ply or obj");
  c->add_option("--labelled", s->labelled,
                "Format of the labelled cloud: ply (the default) or las (LAS 1.4, tree_id, class and height as extra "
                "bytes; the file's classification kept, or set to 2 ground, 5 tree, 1 other where the input had none; "
                "positions, colours and classes only: intensity, returns and times are not carried over)")
      ->default_val(s->labelled);
  c->add_flag("--segment-only", s->segment_only, "Find the trees and write their clouds, table and picture; no models");
  c->add_flag("--keep-leaves", s->keep_leaves,
              "Model every tree from all its points, leafy or not (by default a tree that looks leafy is modelled from "
              "its wood alone, as --wood-if-leafy does)");
  c->add_flag("--html", s->batch.html, "Also write each tree's page and trees/index.html");
  c->add_flag("--preview", s->batch.preview, "Also render each tree's picture (needs Chromium)");
  c->add_option("-j,--jobs", s->batch.jobs, "Trees modelled at once (0: as many as cores)")->default_val(0)->check(CLI::Range(0u, 1024u));
  c->add_flag("--resume", s->batch.resume, "Keep the models of an earlier run whose outputs are all there");
  c->add_flag("-q,--quiet", s->batch.quiet, "Print only failures and the final line");
  const std::string g = "Plot";
  c->add_option("--min-tree-points", s->min_tree_points, "Trees with fewer points are listed but not modelled")
      ->default_val(s->min_tree_points)->group(g);
  c->add_flag("--ground-filter", s->ground_filter,
              "Find the ground by the filter even when the file (LAS, LAZ) classifies points as ground (class 2)")
      ->group(g);
  c->add_option("--ground-cell", s->ground.cell, "Grid step of the ground model")->default_val(s->ground.cell)->check(positive())->group(g);
  c->add_option("--ground-tolerance", s->ground.tolerance, "Points this close above the ground model are ground")
      ->default_val(s->ground.tolerance)->check(not_negative())->group(g);
  c->add_option("--stem-slice", s->stem_slice, "LOW,HIGH: heights above the ground searched for stems (default 0.3,1.8)")->group(g);
  c->add_option("--stem-gap", s->stems.gap, "Slice points closer than this in plan are one stem candidate")
      ->default_val(s->stems.gap)->check(positive())->group(g);
  c->add_option("--voxel", s->segment.voxel, "Voxel edge of the graph the trees are grown on")
      ->default_val(s->segment.voxel)->check(positive())->group(g);
  c->add_option("--max-gap", s->segment.max_gap, "Parts apart from every tree join the nearest one up to this far")
      ->default_val(s->segment.max_gap)->check(not_negative())->group(g);
  add_tree_options(*c, s->batch);
  return [s] { return run(*s); };
}

}  // namespace treeskel::cli
