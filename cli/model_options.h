// The options that shape a tree model (radii, mesh, measurements, the mesh file's frame), shared by
// the commands that make models (model, batch) and by the Python package, so that every front end
// takes the same names, defaults and checks.
#pragma once

#include "treeskel/modeling/radii.h"
#include "treeskel/modeling/sweep.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace treeskel::modeling {
struct TreeMeasurements;
}

namespace treeskel::cli {

struct ModelSettings {
  bool with_skeleton = false;  ///< the skeleton as lines in the mesh file
  bool allow_defects = false;  ///< write a mesh that fails its checks
  modeling::RadiusOptions radii;
  modeling::SweepOptions sweep;
  double breast_height = 1.3;
  bool dbh_from_model = false;
  bool local = false;  ///< mesh files in the local frame
};

/// Adds the options to `command`, in the group "Model".
void add_model_options(CLI::App& command, ModelSettings& settings);

/// The measurements as the reports give them (`measurements` in `model --report`).
nlohmann::ordered_json measurements_json(const modeling::TreeMeasurements& m);

}  // namespace treeskel::cli
