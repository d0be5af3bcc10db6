// Small helpers shared by the command-line subcommands: progress on a terminal, timing, messages.
#pragma once

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

}  // namespace treeskel::cli
