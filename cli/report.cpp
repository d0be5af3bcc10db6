#include "report.h"

#include "treeskel/error.h"
#include "treeskel/io/atomic_file.h"

#include <cmath>
#include <functional>
#include <sstream>

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

void write_report_and_commit(io::OutputSet& outputs, const std::filesystem::path& report_to,
                             const nlohmann::ordered_json& report) {
  try {
    if (!report_to.empty()) io::write_atomically(report_to, [&](std::ostream& out) { out << report.dump(2) << '\n'; });
    outputs.commit();
  } catch (const Error& e) {
    throw Error(outputs.explain(e.what()));
  }
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

namespace {

std::string short_number(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

/// A validator: parses the value as a number and asks `ok`; `says` completes "must be ...".
CLI::Validator number_check(std::function<bool(double)> ok, const std::string& says) {
  return CLI::Validator(
      [ok, says](std::string& text) -> std::string {
        double v = 0.0;
        std::size_t used = 0;
        try {
          v = std::stod(text, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used != text.size() || text.empty()) return "'" + text + "' is not a number";
        if (!ok(v)) return "must be " + says + ", got " + text;
        return {};
      },
      says);
}

}  // namespace

CLI::Validator in_range(double lo, double hi) {
  return number_check([lo, hi](double v) { return v >= lo && v <= hi; },
                      "between " + short_number(lo) + " and " + short_number(hi));
}

CLI::Validator positive() { return number_check([](double v) { return v > 0.0 && std::isfinite(v); }, "a positive number"); }

CLI::Validator not_negative() {
  return number_check([](double v) { return v >= 0.0 && std::isfinite(v); }, "a number not below 0");
}

CLI::Validator off_or_at_least(double lo) {
  return number_check([lo](double v) { return v == 0.0 || (v >= lo && std::isfinite(v)); },
                      "0 (off) or at least " + short_number(lo));
}

std::string format_duration(double seconds) {
  const long t = std::lround(seconds);
  std::ostringstream out;
  if (t >= 3600) out << t / 3600 << "h" << (t % 3600) / 60 << "m";
  else if (t >= 60) out << t / 60 << "m" << t % 60 << "s";
  else out << t << "s";
  return out.str();
}

}  // namespace treeskel::cli
