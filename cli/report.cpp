#include "report.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>

namespace treeskel::cli {

Progress::Progress(bool quiet) : active_(!quiet && ::isatty(STDERR_FILENO)) {}

Progress::~Progress() { clear(); }

void Progress::clear() {
  if (drawn_) std::fprintf(stderr, "\r\033[K");
  drawn_ = false;
}

void Progress::operator()(const std::string& stage, double done) {
  if (!active_) return;
  std::fprintf(stderr, "\r\033[K[%3d%%] %s", static_cast<int>(done * 100.0 + 0.5), stage.c_str());
  std::fflush(stderr);
  drawn_ = true;
}

std::string format_seconds(double seconds) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.2f s", seconds);
  return buffer;
}

double peak_memory_mb() {
  struct rusage usage {};
  ::getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

}  // namespace treeskel::cli
