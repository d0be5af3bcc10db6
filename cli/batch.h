// The batch runner behind `treeskel batch` and `treeskel plot`: each tree converted by a treeskel
// process of its own (so a tree that fails, crashes or runs out of memory fails alone), N at a time,
// with one summary row per tree in summary.csv and summary.json (and index.html with --html).
#pragma once

#include "batch_plan.h"
#include "model_options.h"
#include "skeleton_options.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace treeskel::cli {

struct BatchSettings {
  std::vector<std::string> inputs;
  std::string out_dir;
  std::string model;     ///< mesh format ("" for none)
  std::string model_suffix;  ///< after NAME in the model's file name (plot's "_mesh" for ply, beside the cloud NAME.ply)
  std::string skeleton;  ///< skeleton format ("" for none)
  bool html = false;     ///< a page per tree, and index.html
  bool preview = false;  ///< a PNG per tree (shown in index.html)
  std::size_t html_points = 0;  ///< passed on as given
  unsigned jobs = 0;
  bool resume = false;
  std::string shard;
  bool quiet = false;
  SkeletonSettings method;       ///< checked here, passed on as given
  ModelSettings model_settings;  ///< the same
  std::vector<const CLI::Option*> passed;      ///< the options passed on to every tree's command
  std::vector<const CLI::Option*> model_only;  ///< ... of those, the ones only `model` has
  std::vector<std::string> defaults;           ///< given to every tree's command before those (plot's --wood-if-leafy)
};

/// One tree of the batch and what became of it.
struct BatchRow {
  BatchInput input;
  std::string status = "not run";  ///< ok, failed, not run (the batch was stopped first)
  bool resumed = false;            ///< its outputs were complete from an earlier run
  double seconds = 0.0;
  std::vector<std::filesystem::path> outputs;
  std::filesystem::path report;  ///< the tree's JSON report
  nlohmann::json facts;          ///< that report, once read
  std::string error;
};

/// Adds the options passed on to every tree's command (the model's and the method's, --html-points) to
/// `command`, and lists them in `s.passed` (and those only `model` has in `s.model_only`).
void add_tree_options(CLI::App& command, BatchSettings& s);

/// The points a tree's report says were set aside as leaves: its `wood_only` count, 0 when
/// --wood-if-leafy kept the tree whole, null when neither option ran (or there is no report).
nlohmann::ordered_json leaf_points_of(const nlohmann::json& report);

/// A value of a summary as the text of one CSV cell: a list joined by "; ", null empty.
std::string csv_text(const nlohmann::ordered_json& value);

/// Runs the batch `s` describes; the rows, when asked, once it ends. Returns the exit code: 0 when
/// every tree converted, 1 when any failed, 128 + the signal when it was stopped.
int run_batch(BatchSettings& s, std::vector<BatchRow>* finished = nullptr);

}  // namespace treeskel::cli
