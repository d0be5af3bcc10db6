/// @file run_program.h
/// Runs a helper program (Node.js for LAZ, Chromium for previews) and waits for it.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace treeskel::io {

/// How a program ended.
struct ProgramResult {
  bool started = false;   ///< false: it could not be started (`error` says why)
  int exit_code = -1;     ///< when it exited
  int signal = 0;         ///< when a signal ended it
  std::string error;      ///< why it could not be started
  bool ok() const { return started && signal == 0 && exit_code == 0; }
};

/// Runs `args` (args[0] looked up on the PATH) with stdout to /dev/null and stderr to `log`, and waits.
ProgramResult run_program(const std::vector<std::string>& args, const std::filesystem::path& log);

/// The last line of `file` that is not empty ("" when none): the message a failed helper left.
std::string last_line_of(const std::filesystem::path& file);

}  // namespace treeskel::io
