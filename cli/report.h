// Small helpers shared by the command-line subcommands: progress on a terminal, timing, messages.
#pragma once

#include <CLI/CLI.hpp>

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

/// Formats a number of seconds as "0.42 s".
std::string format_seconds(double seconds);

/// The process's peak resident memory so far, in MB.
double peak_memory_mb();

/// Option checks whose messages print the bounds as they are written ("between 0 and 1", not
/// CLI11's 300-digit rendering of the largest double): a number in [lo, hi], a positive number, a
/// number not below zero.
CLI::Validator in_range(double lo, double hi);
CLI::Validator positive();
CLI::Validator not_negative();

}  // namespace treeskel::cli
