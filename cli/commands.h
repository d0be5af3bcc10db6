// The subcommands of the treeskel tool. Each adds itself to the CLI11 app and returns the function
// that runs it once the command line is parsed.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>

namespace treeskel::cli {

using Command = std::function<int()>;

Command add_skeletonize(CLI::App& app);
Command add_model(CLI::App& app);
Command add_synth(CLI::App& app);
Command add_eval(CLI::App& app);
Command add_batch(CLI::App& app);
Command add_plot(CLI::App& app);


}  // namespace treeskel::cli
