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

/// Extracts the skeleton, naming the input file in the error of a cloud the method refuses.
Skeleton extract_skeleton_of(const std::string& input, const PointCloud& cloud, const SkeletonOptions& options,
                             SkeletonStats* stats);

}  // namespace treeskel::cli
