// The subcommands of the treeskel tool. Each adds itself to the CLI11 app and returns the function
// that runs it once the command line is parsed.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <memory>

namespace treeskel::cli {

using Command = std::function<int()>;

Command add_skeletonize(CLI::App& app);
Command add_model(CLI::App& app);
Command add_synth(CLI::App& app);
Command add_eval(CLI::App& app);
Command add_batch(CLI::App& app);

/// Adds `model`'s options that shape the model (group "Model"; not its input, outputs or printing) to
/// `command`, bound to values the returned handle keeps alive: for a command that checks them and
/// passes them on to `model`.
std::shared_ptr<void> add_model_options(CLI::App& command);

}  // namespace treeskel::cli
