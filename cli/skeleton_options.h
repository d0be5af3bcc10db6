// The method options shared by the commands that extract a skeleton (skeletonize, model).
#pragma once

#include "treeskel/pipeline.h"
#include "treeskel/point_cloud.h"

#include <CLI/CLI.hpp>
#include <Eigen/Core>

#include <string>

namespace treeskel::cli {

struct SkeletonSettings {
  std::string up = "z";
  std::string root;
  std::string neighbours = "octree";
  SkeletonOptions options;
  bool no_prune = false, no_cpc = false, no_refine = false, no_junctions = false, no_smooth = false;
  bool wood_only = false;
  bool ground_aside = false;
};

/// What --wood-only kept and set aside; without it, whether the cloud looked leafy.
struct WoodSplit {
  bool run = false;
  std::size_t wood_points = 0, leaf_points = 0;
  double in_leaf = 0;  ///< 0-1: how much the ways through the points counted (forest::WoodLeaf)
  PointCloud leaves;
  std::string leafy_warning;  ///< without --wood-only: the warning for a leafy cloud, or empty
};

/// Adds the method's options to `command`, in the group "Method".
void add_skeleton_options(CLI::App& command, SkeletonSettings& settings);

/// The options for `cloud`, the command line applied (`--root` is given in the input frame).
SkeletonOptions skeleton_options_for(const SkeletonSettings& settings, const PointCloud& cloud);

/// Checks what the command line gives as text (--up, --root) before any work. @throws OptionError.
void check_skeleton_settings(const SkeletonSettings& settings);

/// Parses "x", "-y", ... or "x,y,z" as a unit direction.
Eigen::Vector3d parse_up(const std::string& text);

/// @throws OptionError unless `path` has an extension skeletons are written in (.ply .obj .json).
void require_skeleton_extension(const std::string& path);

/// With --wood-only: keeps the points of `cloud` that look like wood (forest::separate_wood) and
/// returns the rest as the leaves, saying how many on stderr unless `quiet`. Without it: estimates
/// the share of the points that look like leaves and, from forest::kLeafyShare, returns a warning
/// (without the input's name) for the caller to print and report.
/// @throws InputError when it leaves too few points to extract a skeleton from.
WoodSplit keep_wood(const SkeletonSettings& settings, PointCloud& cloud, const std::string& input, bool quiet);

/// With --set-ground-aside: sets aside the ground the tree's scan stands on, when it holds some
/// (forest::ground_under_tree: ground reaching out beyond the stem's foot), says how many points on
/// stderr unless `quiet`, and returns that count (0 when none was found, or without the option).
std::size_t set_ground_aside(const SkeletonSettings& settings, PointCloud& cloud, const std::string& input, bool quiet);

/// Adds --leaves FILE (the points --wood-only set aside) to `command`.
void add_leaves_option(CLI::App& command, std::string& file);

/// Checks --leaves against --wood-only before any work. @throws OptionError.
void check_leaves_option(const SkeletonSettings& settings, const std::string& file);

/// Extracts the skeleton, naming the input file in the error of a cloud the method refuses.
Skeleton extract_skeleton_of(const std::string& input, const PointCloud& cloud, const SkeletonOptions& options,
                             SkeletonStats* stats);

}  // namespace treeskel::cli
