#include "skeleton_options.h"
#include "model_warnings.h"
#include "report.h"

#include "treeskel/error.h"
#include "treeskel/forest/ground.h"
#include "treeskel/forest/wood.h"
#include "treeskel/io/atomic_file.h"
#include "treeskel/io/skeleton_io.h"
#include "treeskel/modeling/radii.h"

#include <tbb/parallel_invoke.h>

#include <cmath>
#include <iostream>
#include <sstream>

namespace treeskel::cli {

namespace {

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

}  // namespace

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

void add_skeleton_options(CLI::App& c, SkeletonSettings& s) {
  const char* g = "Method";
  SkeletonOptions& o = s.options;
  c.add_flag("--wood-only", s.wood_only,
             "Keep only the points that look like wood for the skeleton and the model: bark is a surface scanned at "
             "least as densely as the foliage, leaves and needles scatter (scored over each point's 40 nearest; no "
             "units); in a cloud in leaf, twigs also carry the shortest ways from the tree's base (its lowest point "
             "along --up) to what lies beyond them, and leaves hang at the ends. On a leafy broadleaf it keeps 90% of "
             "the wood with 9% of what it keeps leaves; on leafless trees it calls up to 10% of the points (thin twigs) "
             "leaves, and on that leafy tree its model reaches 0.94 of the wood's height: so it is off by default. "
             "Without it (or --wood-if-leafy), a cloud in which 16% or more of the points look like leaves gets a "
             "warning. See docs/plots.md")
      ->group(g);
  c.add_flag("--wood-if-leafy", s.wood_if_leafy,
             "As --wood-only, but only when the cloud looks leafy (16% or more of its points look like leaves by shape "
             "and density: the test of the leafy warning); a cloud that does not is kept whole, so leafless trees lose "
             "no twigs. The report's wood_if_leafy says what was estimated and decided. Plot's default for each tree")
      ->group(g);
  c.add_flag("--set-ground-aside", s.ground_aside,
             "Set aside the ground a single tree's scan stands on, and what lies on it below 0.3 m, before the "
             "skeleton (counted on stderr and in the report's ground_set_aside): the skeleton roots in a disc of "
             "ground and the pipe model spreads the trunk's radius over it (TreeLS's pine: a trunk 0.10 m across in "
             "the model where the points give 0.26 m; 0.25 m with this option). The ground is found by a progressive "
             "morphological filter (metres assumed) and taken only when a stem stands on it and it reaches beyond "
             "three stem radii; the stem's own foot stays. Off by default: it moves the skeleton's base, and on "
             "whorled conifers the result can still be off (docs/models.md)")
      ->group(g);
  c.add_option("--up", s.up, "Axis the tree grows along: x, y, z, -x, -y, -z or 'x,y,z'")->default_val("z")->group(g);
  c.add_option("--root", s.root, "Point 'x,y,z' (input frame) where the tree stands (default: lowest part of the cloud)")->group(g);
  c.add_option("--root-slice", o.root.slice, "Thickness of the trunk base slice the geodesic distance starts from (0: two cells)")
      ->default_val(o.root.slice)->group(g);
  c.add_option("--depth", o.octree.depth, "Octree depth (0: the deepest whose cells hold --cell-points points on average)")
      ->default_val(o.octree.depth)->check(in_range(0, 21))->group(g);
  c.add_option("--cell-points", o.octree.points_per_cell,
                "Mean points per octree cell that sets the depth (0: the paper's depth, 2 + log8 N)")
      ->default_val(o.octree.points_per_cell)->check(not_negative())->group(g);
  c.add_option("--depth-steps", o.octree.depth_steps,
                "Cell sizes between two octree depths: with --depth 0, the cube is also tried grown by 2^(k/N), "
                "k < N, and the finest cell that holds --cell-points wins, so the cell does not jump by 2 with the "
                "point count (docs/accuracy.md). Only for clouds of up to " +
                    std::to_string(o.octree.depth_steps_max_points) + " points. 1: whole depths only")
      ->default_val(o.octree.depth_steps)->check(in_range(1, 16))->group(g);
  c.add_option("--neighbours", s.neighbours, "Neighbour graph: 'octree' (26-adjacent cells) or 'knn' (k nearest skeleton points)")
      ->default_val("octree")->check(CLI::IsMember({"octree", "knn"}))->group(g);
  c.add_option("--reach", o.graph.reach, "With --neighbours octree: cells this many cells apart are neighbours (1: the paper's 26)")
      ->default_val(o.graph.reach)->check(in_range(1, 3))->group(g);
  c.add_option("-k", o.graph.k, "Neighbours per skeleton point with --neighbours knn")->default_val(o.graph.k)
      ->check(in_range(1, 1000))->group(g);
  c.add_option("--bridge", o.graph.bridge_distance,
                "Join parts of the cloud whose gap is at most this long (0: 4 cells; negative: never)")
      ->default_val(o.graph.bridge_distance)->group(g);
  c.add_option("--far-bridge-points", o.graph.far_bridge_min_points,
                "Parts of at least this many points are also joined across gaps up to a tenth of the cloud's size "
                "(a twig cut off by an occlusion); smaller ones only across --bridge")
      ->default_val(o.graph.far_bridge_min_points)->check(in_range(1, 1000000))->group(g);
  c.add_option("--small-cluster", o.graph.small_cluster_fraction,
                "Parts left apart that hold less than this share of the points are reported as noise")
      ->default_val(o.graph.small_cluster_fraction)->check(in_range(0.0, 1.0))->group(g);
  c.add_option("--band", o.level_sets.band_width, "Width of a level set band of geodesic distance (0: 2 cells)")
      ->default_val(o.level_sets.band_width)->check(not_negative())->group(g);
  c.add_option("--prune-length", o.prune.min_length, "Remove leaf branches shorter than this (0: --prune-bands bands)")
      ->default_val(o.prune.min_length)->check(not_negative())->group(g);
  c.add_option("--prune-bands", o.prune.min_bands,
               "With --prune-length 0, the shortest leaf branch kept in bands (skeletonize: 0.5, which the radius "
               "rule implies anyway; a model: 1, leaving out short twigs that cost the mesh time; docs/models.md)")
      ->default_val(o.prune.min_bands)->check(not_negative())->group(g);
  c.add_option("--close-forks", o.prune.close_forks,
               "At a fork this many bands or less from another along the skeleton, remove its shortest leaf arm "
               "of at most 3 bands: one true fork the level sets made two (skeletonize: 1.5; a model: 0, off, "
               "keeping those twigs for the mesh; docs/accuracy.md)")
      ->default_val(o.prune.close_forks)->check(not_negative())->group(g);
  c.add_option("--prune-radius", o.prune.radius_factor,
               "... or that stay within this many of their host's nodes' radii, where --prune-point-radius is 0 "
               "(a model: 1, keeping more twigs for the mesh to show; docs/models.md) or the host holds no "
               "points (skeletonize: 1.75)")
      ->default_val(o.prune.radius_factor)->check(not_negative())->group(g);
  c.add_option("--prune-point-radius", o.prune.point_host_factor,
               "The radius rule with the points' help: a leaf branch goes when it stays within this many times its "
               "host's radius, the smaller of its nodes' median radius (which a twig leaving at the fork inflates) "
               "and the median distance of its points from its axis (which foliage inflates) (skeletonize: 2.25). "
               "0: the nodes' radii alone, with --prune-radius (a model's; docs/accuracy.md)")
      ->default_val(o.prune.point_host_factor)->check(not_negative())->group(g);
  c.add_option("--cpc-weight", o.cpc.weight, "Weight w of the equal-distance (cylinder) term of CPC")
      ->default_val(o.cpc.weight)->check(not_negative())->group(g);
  c.add_option("--eta", o.refine.eta, "Refinement threshold factor eta of eq. 8")->default_val(o.refine.eta)
      ->check(not_negative())->group(g);
  c.add_option("--samples", o.smooth.samples_per_edge, "Spline points inserted between adjacent nodes")
      ->default_val(o.smooth.samples_per_edge)->check(in_range(0, 100))->group(g);
  c.add_option("--tension", o.smooth.tension, "Cardinal spline tension (0: Catmull-Rom, 1: straight)")
      ->default_val(o.smooth.tension)->check(in_range(0.0, 1.0))->group(g);
  c.add_flag("--no-prune", s.no_prune, "Keep every level-set branch, however short")->group(g);
  c.add_flag("--no-cpc", s.no_cpc, "Skip the cylindrical prior constraint (nodes stay at L1-medians)")->group(g);
  c.add_flag("--no-refine", s.no_refine, "Skip the topology refinement at branch nodes")->group(g);
  c.add_flag("--no-junctions", s.no_junctions, "Leave forks where the level sets put them (no axis-meeting placement)")->group(g);
  c.add_flag("--no-smooth", s.no_smooth, "Skip the spline smoothing")->group(g);
}

void check_skeleton_settings(const SkeletonSettings& s) {
  if (s.wood_only && s.wood_if_leafy)
    throw OptionError("--wood-only and --wood-if-leafy: give one (--wood-only sets leaves aside from every cloud, "
                      "--wood-if-leafy only from a cloud that looks leafy)");
  parse_up(s.up);
  if (!s.root.empty()) parse_vector(s.root, "--root");
}

void use_model_defaults(SkeletonSettings& s) { modeling::use_model_pruning(s.options.prune); }

SkeletonOptions skeleton_options_for(const SkeletonSettings& s, const PointCloud& cloud) {
  SkeletonOptions o = s.options;
  o.root.up = parse_up(s.up);
  if (!s.root.empty()) o.root.point = parse_vector(s.root, "--root") - cloud.offset;
  if (s.neighbours == "knn") o.graph.mode = NeighbourMode::knn;
  o.use_prune = !s.no_prune;
  o.use_cpc = !s.no_cpc;
  o.use_refine = !s.no_refine;
  o.use_junctions = !s.no_junctions;
  o.use_smooth = !s.no_smooth;
  return o;
}

void require_skeleton_extension(const std::string& path) {
  if (!io::is_skeleton_extension(path))
    throw OptionError(path + ": unknown skeleton extension '." + io::extension_of(path) + "'; use .ply, .obj or .json");
}

std::size_t set_ground_aside(const SkeletonSettings& s, PointCloud& cloud, const std::string& input, bool quiet) {
  if (!s.ground_aside) return 0;
  const forest::GroundUnderTree g = forest::ground_under_tree(cloud, parse_up(s.up));
  if (g.ground_points == 0) return 0;
  cloud = forest::select_points(cloud, g.is_ground, 0);
  if (!quiet) std::cerr << "note: " << input << ": " << ground_note(g.ground_points, "--set-ground-aside") << '\n';
  return g.ground_points;
}

WoodSplit keep_wood(const SkeletonSettings& s, PointCloud& cloud, const std::string& input, bool quiet) {
  WoodSplit split;
  if (!may_set_leaves_aside(s)) {
    split.leafy_warning = leafy_warning(cloud);
    return split;
  }
  const char* option = leaves_option(s);
  if (s.wood_if_leafy) {
    split.estimated_leaf_share = forest::estimate_leaf_share(cloud);
    if (split.estimated_leaf_share < forest::kLeafyShare) return split;  // kept whole
  }
  forest::WoodOptions options;
  options.up = parse_up(s.up);
  const forest::WoodLeaf w = forest::separate_wood(cloud, options);
  split.run = true;
  split.wood_points = w.wood_points;
  split.leaf_points = w.leaf_points;
  split.in_leaf = w.in_leaf;
  split.leaves = forest::select_points(cloud, w.is_wood, 0);
  const std::size_t all = cloud.size();
  cloud = forest::select_points(cloud, w.is_wood, 1);
  if (!quiet) {
    std::cerr << option << ": ";
    if (s.wood_if_leafy)
      std::cerr << "the cloud looks leafy (about " << std::lround(100.0 * split.estimated_leaf_share)
                << "% of its points look like leaves or needles); ";
    std::cerr << wood_split(w.wood_points, w.leaf_points, w.in_leaf) << '\n';
  }
  if (cloud.size() < kFewestWoodPoints)
    throw InputError(input + ": " + option + " found " + std::to_string(cloud.size()) + " of " + std::to_string(all) +
                     " points that look like wood; too few for a skeleton (" +
                     (s.wood_only ? "leave --wood-only off" : "keep the leaves: leave --wood-if-leafy off, or plot's --keep-leaves") + ")");
  return split;
}

WoodSplit keep_wood_then(const SkeletonSettings& s, PointCloud& cloud, const std::string& input, bool quiet,
                         const std::function<void()>& extract) {
  WoodSplit split;
  if (may_set_leaves_aside(s)) {
    split = keep_wood(s, cloud, input, quiet);
    extract();
  } else {
    tbb::parallel_invoke([&] { split = keep_wood(s, cloud, input, quiet); }, extract);
  }
  return split;
}

void report_wood(const WoodSplit& w, nlohmann::ordered_json& j) {
  if (w.run) j["wood_only"] = {{"wood_points", w.wood_points}, {"leaf_points", w.leaf_points}, {"in_leaf", w.in_leaf}};
  if (w.estimated_leaf_share >= 0.0)
    j["wood_if_leafy"] = {{"estimated_leaf_share", std::round(1000.0 * w.estimated_leaf_share) / 1000.0},
                          {"leaves_set_aside", w.run}};
}

void add_leaves_option(CLI::App& c, std::string& file) {
  c.add_option("--leaves", file,
               "With --wood-only or --wood-if-leafy: also write the points set aside as leaves to this cloud file (.ply, "
               ".xyz, ...); with --wood-if-leafy and a cloud that does not look leafy, a cloud of no points");
}

void check_leaves_option(const SkeletonSettings& s, const std::string& file) {
  if (!file.empty() && !may_set_leaves_aside(s))
    throw OptionError("--leaves " + file + " needs --wood-only or --wood-if-leafy (it writes the points they set aside)");
}

Skeleton extract_skeleton_of(const std::string& input, const PointCloud& cloud, const SkeletonOptions& options,
                             SkeletonStats* stats) {
  try {
    return extract_skeleton(cloud, options, stats);
  } catch (const InputError& e) {
    throw InputError(input + ": " + e.what());
  }
}

}  // namespace treeskel::cli
