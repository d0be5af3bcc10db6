// The method options shared by the commands that extract a skeleton (skeletonize, model).
#pragma once

#include "treeskel/pipeline.h"
#include "treeskel/point_cloud.h"

#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <functional>
#include <string>

namespace treeskel::cli {

struct SkeletonSettings {
  std::string up = "z";
  std::string root;
  std::string neighbours = "octree";
  SkeletonOptions options;
  bool no_prune = false, no_cpc = false, no_refine = false, no_junctions = false, no_smooth = false;
  bool wood_only = false;
  bool wood_if_leafy = false;  ///< --wood-if-leafy: as --wood-only, when the cloud looks leafy (plot's default)
  bool ground_aside = false;
};

/// What --wood-only (or --wood-if-leafy) kept and set aside; without them, whether the cloud looked leafy.
struct WoodSplit {
  bool run = false;  ///< the leaves were looked for and set aside
  std::size_t wood_points = 0, leaf_points = 0;
  double in_leaf = 0;  ///< 0-1: how much the ways through the points counted (forest::WoodLeaf)
  PointCloud leaves;   ///< empty when none were set aside
  std::string leafy_warning;  ///< without either option: the warning for a leafy cloud, or empty
  /// With --wood-if-leafy: forest::estimate_leaf_share, which decided (from forest::kLeafyShare); else -1.
  double estimated_leaf_share = -1.0;
};

/// Whether the command sets leaves aside, always or when the cloud looks leafy (so writes --leaves).
inline bool may_set_leaves_aside(const SkeletonSettings& s) { return s.wood_only || s.wood_if_leafy; }

/// The option that sets leaves aside, as the user gave it ("--wood-only" or "--wood-if-leafy"), for messages.
inline const char* leaves_option(const SkeletonSettings& s) { return s.wood_only ? "--wood-only" : "--wood-if-leafy"; }

/// Adds the method's options to `command`, in the group "Method".
void add_skeleton_options(CLI::App& command, SkeletonSettings& settings);

/// What a command that writes a model starts from: the model's pruning (modeling::use_model_pruning,
/// where skeletonize keeps the skeleton's). Call before add_skeleton_options, so that --help shows it
/// and the command line still sets it.
void use_model_defaults(SkeletonSettings& settings);

/// The options for `cloud`, the command line applied (`--root` is given in the input frame).
SkeletonOptions skeleton_options_for(const SkeletonSettings& settings, const PointCloud& cloud);

/// Checks what the command line gives as text (--up, --root) before any work. @throws OptionError.
void check_skeleton_settings(const SkeletonSettings& settings);

/// Parses "x", "-y", ... or "x,y,z" as a unit direction.
Eigen::Vector3d parse_up(const std::string& text);

/// @throws OptionError unless `path` has an extension skeletons are written in (.ply .obj .json).
void require_skeleton_extension(const std::string& path);

/// With --wood-only: keeps the points of `cloud` that look like wood (forest::separate_wood) and
/// returns the rest as the leaves, saying how many on stderr unless `quiet`. With --wood-if-leafy: the
/// same when forest::estimate_leaf_share calls the cloud leafy (from forest::kLeafyShare), else the
/// cloud is kept whole. Without either: estimates that share and, from kLeafyShare, returns a warning
/// (without the input's name) for the caller to print and report.
/// @throws InputError when it leaves too few points to extract a skeleton from.
WoodSplit keep_wood(const SkeletonSettings& settings, PointCloud& cloud, const std::string& input, bool quiet);

/// `keep_wood`, then `extract` (the skeleton of the cloud it leaves). Where the settings set no leaves
/// aside, `keep_wood` only looks for a leafy cloud to warn about and changes nothing: it then runs
/// beside `extract` (on a 1 M-point cloud the look takes 0.05 s, and the skeleton's stages that run on
/// one core leave the other free for it).
WoodSplit keep_wood_then(const SkeletonSettings& settings, PointCloud& cloud, const std::string& input, bool quiet,
                         const std::function<void()>& extract);

/// Adds what `wood` did to a command's report: `wood_only` (points kept and set aside) when leaves
/// were set aside, `wood_if_leafy` (the estimated share and whether it set them aside) with that option.
void report_wood(const WoodSplit& wood, nlohmann::ordered_json& report);

/// With --set-ground-aside: sets aside the ground the tree's scan stands on, when it holds some
/// (forest::ground_under_tree: ground reaching out beyond the stem's foot), says how many points on
/// stderr unless `quiet`, and returns that count (0 when none was found, or without the option).
std::size_t set_ground_aside(const SkeletonSettings& settings, PointCloud& cloud, const std::string& input, bool quiet);

/// Adds --leaves FILE (the points --wood-only or --wood-if-leafy set aside) to `command`.
void add_leaves_option(CLI::App& command, std::string& file);

/// Checks --leaves against --wood-only and --wood-if-leafy before any work. @throws OptionError.
void check_leaves_option(const SkeletonSettings& settings, const std::string& file);

/// Extracts the skeleton, naming the input file in the error of a cloud the method refuses.
Skeleton extract_skeleton_of(const std::string& input, const PointCloud& cloud, const SkeletonOptions& options,
                             SkeletonStats* stats);

}  // namespace treeskel::cli
