// Small helpers shared by the command-line subcommands: progress on a terminal, timing, messages.
#pragma once

#include "treeskel/io/output_set.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <string>

namespace treeskel::cli {

/// Prints "[ 40%] stage" on stderr, overwriting itself, when stderr is a terminal and not quiet.
class Progress {
public:
  explicit Progress(bool quiet);
  ~Progress();
  void operator()(const std::string& stage, double done);
  /// Erases the progress line (before the summary is printed).
  void clear();
  bool active() const { return active_; }

private:
  bool active_ = false;
  bool drawn_ = false;
};

class Stopwatch {
public:
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

/// Writes `report` (when `report_to`, a staged path of `outputs`, is not empty) and commits every output
/// of the run; a failed write names the file as the user named it.
void write_report_and_commit(io::OutputSet& outputs, const std::filesystem::path& report_to,
                             const nlohmann::ordered_json& report);

/// Formats a duration for a person: "42s", "3m20s", "1h05m".
std::string format_duration(double seconds);

/// Formats a number of seconds as "0.42 s".
std::string format_seconds(double seconds);

/// The process's peak resident memory so far, in MB.
double peak_memory_mb();

/// Option checks whose messages print the bounds as they are written ("between 0 and 1", not
/// CLI11's 300-digit rendering of the largest double): a number in [lo, hi], a positive number, a
/// number not below zero, 0 (off) or a number of at least lo.
CLI::Validator in_range(double lo, double hi);
CLI::Validator positive();
CLI::Validator not_negative();
CLI::Validator off_or_at_least(double lo);

}  // namespace treeskel::cli
