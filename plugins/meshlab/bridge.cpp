// The plugin's calls into the library (C++17). Nothing here is MeshLab's: plain arrays in and out.
#include "bridge.h"

#include "model_warnings.h"

#include "treeskel/error.h"
#include "treeskel/forest/wood.h"
#include "treeskel/modeling/coverage.h"
#include "treeskel/modeling/measurements.h"
#include "treeskel/modeling/radii.h"
#include "treeskel/modeling/sweep.h"
#include "treeskel/pipeline.h"

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <new>
#include <sstream>

namespace treeskel::meshlab {

namespace {

PointCloud cloud_of(const std::vector<double>& xyz) {
  if (xyz.size() % 3 != 0) throw InputError("the coordinates are not a whole number of points");
  PointCloud cloud;
  cloud.positions.reserve(xyz.size() / 3);
  for (std::size_t i = 0; i + 2 < xyz.size(); i += 3) cloud.positions.emplace_back(xyz[i], xyz[i + 1], xyz[i + 2]);
  recentre_offset(cloud);
  return cloud;
}

Eigen::Vector3d up_of(const SkeletonParams& p) {
  const Eigen::Vector3d up(p.up[0], p.up[1], p.up[2]);
  if (!(up.norm() > 0.0)) throw OptionError("the up axis must not be the zero vector");
  return up.normalized();
}

/// Every field the plugin shares with the library's options, once: `copy(param, option)` is called
/// for each pair, so one table serves both directions.
template <class Params, class Options, class Copy>
void skeleton_fields(Params& p, Options& o, Copy copy) {
  copy(p.octree_depth, o.octree.depth);
  copy(p.points_per_cell, o.octree.points_per_cell);
  copy(p.band_width, o.level_sets.band_width);
  copy(p.prune_length, o.prune.min_length);
  copy(p.bridge_distance, o.graph.bridge_distance);
  copy(p.cpc_weight, o.cpc.weight);
  copy(p.eta, o.refine.eta);
  copy(p.samples, o.smooth.samples_per_edge);
  copy(p.tension, o.smooth.tension);
  copy(p.prune, o.use_prune);
  copy(p.cpc, o.use_cpc);
  copy(p.refine, o.use_refine);
  copy(p.junctions, o.use_junctions);
  copy(p.smooth, o.use_smooth);
}

template <class Params, class Radii, class Sweep, class Copy>
void model_fields(Params& p, Radii& r, Sweep& s, Copy copy) {
  copy(p.exponent, r.exponent);
  copy(p.tip_weight, r.tip_weight);
  copy(p.complete, r.complete);
  copy(p.complete_all, r.completion.tufts_and_bushes);
  copy(p.segments, s.trunk_segments);
  copy(p.min_segments, s.min_segments);
  copy(p.min_radius, s.min_radius);
  copy(p.repair, s.repair);
}

const auto to_params = [](auto& param, const auto& option) { param = option; };
const auto to_options = [](const auto& param, auto& option) { option = param; };

SkeletonOptions options_of(const SkeletonParams& p) {
  SkeletonOptions o;
  o.root.up = up_of(p);
  skeleton_fields(p, o, to_options);
  return o;
}

struct ModelOptions {
  modeling::RadiusOptions radii;
  modeling::SweepOptions sweep;
};

ModelOptions options_of(const ModelParams& p) {
  ModelOptions o;
  model_fields(p, o.radii, o.sweep, to_options);
  return o;
}

/// Reports progress from `begin` to `end` percent as the library's share `done` of its work grows.
void report(ProgressFn progress, const std::string& stage, double done, int begin, int end) {
  if (progress) progress(begin + static_cast<int>(done * (end - begin)), stage.c_str());
}

/// The skeleton of `cloud` with radii from the pipe model, reporting progress in [0, end] percent.
/// `for_mesh`: pruned as `treeskel model` prunes (modeling::use_model_pruning), else as skeletonize.
/// `bushes`: the warning when the completion left the bushes out (cli::bushes_left_out), or empty.
Skeleton skeleton_of(const PointCloud& cloud, const SkeletonParams& sp, const ModelParams& mp, ProgressFn progress,
                     int end, bool for_mesh, std::string& bushes) {
  SkeletonOptions o = options_of(sp);
  if (for_mesh) modeling::use_model_pruning(o.prune);
  const int skeleton_end = end * 9 / 10;
  if (progress) o.progress = [&](const std::string& stage, double done) { report(progress, stage, done, 0, skeleton_end); };
  SkeletonStats stats;
  Skeleton skeleton = extract_skeleton(cloud, o, &stats);
  report(progress, "fitting radii", 1.0, 0, skeleton_end);
  modeling::RadiusOptions radii = options_of(mp).radii;
  radii.cell_size = stats.cell_size;  // the scale of the completion's margins
  modeling::RadiusStats radius_stats;
  modeling::fit_radii(skeleton, &cloud, radii, &radius_stats);
  bushes = cli::bushes_left_out(radius_stats.completion, cloud.size(), "\"Grow through missed points\" set to every group",
                                "the filter's \"Wood only\" option");
  return skeleton;
}

void append(std::vector<double>& xyz, const Eigen::Vector3d& p) {
  xyz.push_back(p.x());
  xyz.push_back(p.y());
  xyz.push_back(p.z());
}

std::string format(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", value);
  return text;
}

/// MeshLab holds coordinates as 32-bit floats: far from the origin (a georeferenced cloud) they lie
/// on a coarse grid. From this share of the cloud's extent a step of that grid is a warning (twigs
/// lose their shape), from the second an error (whole branches do: arbor's tree at its UTM
/// coordinates, read by MeshLab, has ten distinct northings 0.5 apart).
constexpr double kFloatGridWarning = 1e-4;
constexpr double kFloatGridError = 1e-3;

/// The float grid's step where the cloud `xyz` lies, against its extent: empty when fine, else the
/// warning; throws InputError when too coarse for a skeleton.
std::string float_grid_check(const std::vector<double>& xyz) {
  Eigen::AlignedBox3d box;
  for (std::size_t i = 0; i + 2 < xyz.size(); i += 3) box.extend(Eigen::Vector3d(xyz[i], xyz[i + 1], xyz[i + 2]));
  if (box.isEmpty()) return {};
  const double extent = box.diagonal().norm();
  double farthest = 0.0, step = 0.0;
  for (int a = 0; a < 3; ++a) {
    const float far = static_cast<float>(std::max(std::abs(box.min()[a]), std::abs(box.max()[a])));
    const double spacing = static_cast<double>(std::nextafter(far, std::numeric_limits<float>::infinity()) - far);
    if (spacing > step) step = spacing, farthest = static_cast<double>(far);
  }
  if (!(extent > 0.0) || step <= kFloatGridWarning * extent) return {};
  std::ostringstream w;
  w << "the cloud's coordinates reach " << format(farthest) << ", where MeshLab's 32-bit floats are " << format(step)
    << " apart (1/" << std::lround(extent / step) << " of the cloud's extent, " << format(extent)
    << "): MeshLab rounded the points to that grid when it read them";
  if (step > kFloatGridError * extent)
    throw InputError(w.str() + ", too coarse for a skeleton. Move the cloud near the origin before loading it (subtract a "
                     "point near the cloud from every coordinate, e.g. PDAL's filters.transformation or CloudCompare's "
                     "global shift), or use the treeskel command or Python package, which read coordinates as doubles");
  w << ", and the thinnest twigs lose their shape; for full detail move the cloud near the origin before loading it";
  return w.str();
}

/// The points a filter makes its skeleton of, and what the log says about them.
struct Source {
  PointCloud cloud;             // the cloud, or its wood with `wood_only`
  std::vector<double> leaves;   // with `wood_only`: the points set aside, in the input's frame
  std::string wood;             // with `wood_only`: the split, one line
  std::string leafy;            // without it: the warning of a cloud that looks leafy, or empty
  std::string float_grid;       // the warning of a cloud far from the origin, or empty
  std::string bushes;           // the warning of bushes the completion left out, or empty
};

/// The cloud `xyz`, or with `wood_only` the points of it that look like wood (forest::separate_wood,
/// as `--wood-only` keeps them); without it, the leafy warning when the cloud looks leafy.
Source source_of(const std::vector<double>& xyz, const SkeletonParams& sp) {
  Source s;
  s.float_grid = float_grid_check(xyz);
  s.cloud = cloud_of(xyz);
  if (!sp.wood_only) {
    s.leafy = cli::leafy_warning(s.cloud, "the filter's \"Wood only\" option");
    return s;
  }
  forest::WoodOptions options;
  options.up = up_of(sp);
  const forest::WoodLeaf w = forest::separate_wood(s.cloud, options);
  const PointCloud leaves = forest::select_points(s.cloud, w.is_wood, 0);
  s.leaves.reserve(3 * leaves.size());
  for (const auto& p : leaves.positions) append(s.leaves, p + leaves.offset);
  const std::size_t all = s.cloud.size();
  s.cloud = forest::select_points(s.cloud, w.is_wood, 1);
  s.wood = "treeskel: wood only: " + cli::wood_split(w.wood_points, w.leaf_points, w.in_leaf);
  if (s.cloud.size() < cli::kFewestWoodPoints)
    throw InputError("\"Wood only\" found " + std::to_string(s.cloud.size()) + " of " + std::to_string(all) +
                     " points that look like wood; too few for a skeleton (turn it off)");
  return s;
}

/// Hands what `source` has for the log and the leaves layer to `notes`, its warnings first.
void take_notes(Source& source, LayerNotes& notes) {
  notes.wood = std::move(source.wood);
  notes.leaves = std::move(source.leaves);
  for (std::string* w : {&source.float_grid, &source.leafy, &source.bushes})
    if (!w->empty()) notes.warnings.push_back(std::move(*w));
}

/// Runs `work`, turning every exception into `error` and false.
template <class Work>
bool guarded(std::string& error, Work&& work) {
  try {
    work();
    return true;
  } catch (const std::bad_alloc&) {
    error = "treeskel ran out of memory";
  } catch (const std::exception& e) {
    error = e.what();
  } catch (...) {
    error = "treeskel failed with an unknown error";
  }
  return false;
}

}  // namespace

SkeletonParams default_skeleton_params() {
  SkeletonParams p;
  const SkeletonOptions o;
  skeleton_fields(p, o, to_params);
  return p;
}

ModelParams default_model_params() {
  ModelParams p;
  const ModelOptions o;
  model_fields(p, o.radii, o.sweep, to_params);
  p.breast_height = modeling::MeasureOptions{}.breast_height;
  return p;
}

bool resolve_scales(const std::vector<double>& xyz, SkeletonParams& params, std::string& error, bool for_mesh) {
  return guarded(error, [&] {
    SkeletonOptions given = options_of(params);
    if (for_mesh) modeling::use_model_pruning(given.prune);
    const SkeletonOptions o = automatic_options(cloud_of(xyz), given);
    const int depth = params.octree_depth;
    skeleton_fields(params, o, to_params);
    params.octree_depth = depth;  // a cell size between two depths' is not a depth: 0 stays automatic
  });
}

bool tree_skeleton(const std::vector<double>& xyz, const SkeletonParams& sp, const ModelParams& mp,
                   ProgressFn progress, SkeletonLayer& out, std::string& error) {
  return guarded(error, [&] {
    Source source = source_of(xyz, sp);
    const PointCloud& cloud = source.cloud;
    const Skeleton skeleton = skeleton_of(cloud, sp, mp, progress, 100, false, source.bushes);
    SkeletonLayer layer;
    take_notes(source, layer);
    for (NodeId v = 0; v < skeleton.node_count(); ++v) {
      append(layer.xyz, skeleton[v].position + skeleton.offset);
      layer.radius.push_back(skeleton[v].radius);
    }
    for (const auto e : boost::make_iterator_range(boost::edges(skeleton.graph))) {
      layer.edges.push_back(static_cast<int>(boost::source(e, skeleton.graph)));
      layer.edges.push_back(static_cast<int>(boost::target(e, skeleton.graph)));
    }
    std::ostringstream summary;
    summary << "treeskel: " << cloud.size() << " points -> " << skeleton.node_count() << " nodes, "
            << count_branch_points(skeleton.graph) << " branch points, " << count_endpoints(skeleton.graph)
            << " endpoints; trunk radius " << format(skeleton[skeleton.root].radius);
    layer.summary = summary.str();
    report(progress, "done", 1.0, 0, 100);
    out = std::move(layer);
  });
}

bool tree_mesh(const std::vector<double>& xyz, const SkeletonParams& sp, const ModelParams& mp, ProgressFn progress,
               MeshLayer& out, std::string& error) {
  return guarded(error, [&] {
    Source source = source_of(xyz, sp);
    const PointCloud& cloud = source.cloud;
    const Skeleton skeleton = skeleton_of(cloud, sp, mp, progress, 70, true, source.bushes);
    report(progress, "sweeping the mesh", 0.7, 0, 100);
    const modeling::SweepOptions so = options_of(mp).sweep;
    modeling::SweepStats stats;
    const modeling::TreeMesh mesh = modeling::sweep_mesh(skeleton, so, &stats);
    report(progress, "checking the mesh", 0.9, 0, 100);
    const modeling::MeshCheck check = cli::check_swept(mesh, stats, so.repair);
    if (!check.ok() && !cli::only_apart(check) && !mp.allow_defects)
      throw Error("the tree mesh failed its check: " + check.problem() + " (\"Keep a defective mesh\" adds it anyway)");

    MeshLayer layer;
    layer.xyz.reserve(3 * mesh.n_vertices());
    for (const auto v : mesh.vertices()) {
      const auto& p = mesh.point(v);
      append(layer.xyz, Eigen::Vector3d(p[0], p[1], p[2]) + skeleton.offset);
    }
    layer.triangles.reserve(3 * mesh.n_faces());
    for (const auto f : mesh.faces())
      for (const auto v : mesh.fv_range(f)) layer.triangles.push_back(v.idx());

    modeling::MeasureOptions mo;
    mo.up = up_of(sp);
    mo.breast_height = mp.breast_height;
    const modeling::TreeMeasurements m = modeling::measure_tree(skeleton, &cloud, mo);
    std::ostringstream summary;
    summary << "treeskel: " << cloud.size() << " points -> " << skeleton.node_count() << " nodes -> "
            << check.faces << " triangles ("
            << (check.ok() ? (so.repair ? "closed, manifold, no self-intersection" : "closed, manifold") : check.problem())
            << "); height " << format(m.height) << ", DBH "
            << (!m.dbh ? std::string("n/a")
                       : format(*m.dbh) + modeling::dbh_note(m))
            << ", wood volume " << format(m.volume);
    const modeling::SkeletonCoverage coverage = modeling::skeleton_coverage(skeleton, mesh);
    summary << "; " << std::lround(100.0 * coverage.share()) << "% of the skeleton inside the mesh ("
            << std::lround(100.0 * coverage.wood.share()) << "% of its wood)";
    if (stats.pieces > 0) summary << " (" << stats.pieces << " limbs swept apart and united)";
    if (stats.thin_left_out + stats.pieces_failed > 0)
      summary << "; " << stats.thin_left_out + stats.pieces_failed << " branches left out";
    layer.summary = summary.str();
    take_notes(source, layer);
    for (auto& w : cli::model_warnings({skeleton, mo.up, m, mp.breast_height, check, stats, coverage, so.unite_apart}))
      layer.warnings.push_back(std::move(w));
    report(progress, "done", 1.0, 0, 100);
    out = std::move(layer);
  });
}

}  // namespace treeskel::meshlab
