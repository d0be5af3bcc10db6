// Speed and peak memory of reading a cloud and extracting its skeleton.
//
//   bench_speed [--synthetic N,N,...] [--keep DIR] [--repeat R] [--threads T] [FILE...]
//
// Synthetic clouds are random trees (eval::grow_tree) sampled with N points and written as binary
// PLY to a temporary folder (or DIR, kept) first; their generation is not timed. Each input then runs in a child
// process of its own, so that its peak resident memory (from wait4) is its own. Prints a Markdown
// table: the time to read the file, the time to extract the skeleton (best of R runs), the points per
// second of both together, the peak memory, and the slowest stage.
#include "treeskel/eval/cylinders.h"
#include "treeskel/eval/tree_generator.h"
#include "treeskel/io/point_cloud_io.h"
#include "treeskel/pipeline.h"

#include <nlohmann/json.hpp>
#include <sys/resource.h>
#include <sys/wait.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace treeskel;

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

std::string measure(const std::string& path, int repeat) {
  const double t0 = now();
  const PointCloud cloud = io::read_point_cloud(path);
  const double read = now() - t0;
  double best = 1e300;
  SkeletonStats stats;
  Skeleton skeleton;
  for (int r = 0; r < repeat; ++r) {
    const double t1 = now();
    skeleton = extract_skeleton(cloud, {}, &stats);
    best = std::min(best, now() - t1);
  }
  std::string slowest;
  double slowest_s = -1.0;
  for (const auto& [stage, s] : stats.seconds)
    if (s > slowest_s) slowest_s = s, slowest = stage;
  nlohmann::json j;
  j["points"] = cloud.size();
  j["read"] = read;
  j["skeleton"] = best;
  j["nodes"] = skeleton.node_count();
  j["cells"] = stats.cells;
  j["slowest"] = slowest;
  j["slowest_share"] = slowest_s / best;
  return j.dump();
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> files;
  std::vector<std::size_t> synthetic;
  int repeat = 3;
  unsigned threads = 0;
  std::string keep;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--synthetic" && i + 1 < argc) {
      std::stringstream list(argv[++i]);
      for (std::string n; std::getline(list, n, ',');) synthetic.push_back(std::stoull(n));
    } else if (a == "--keep" && i + 1 < argc) {
      keep = argv[++i];
    } else if (a == "--repeat" && i + 1 < argc) {
      repeat = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--threads" && i + 1 < argc) {
      threads = static_cast<unsigned>(std::atoi(argv[++i]));
    } else if (a == "--help" || a == "-h") {
      std::cout << "usage: bench_speed [--synthetic N,N,...] [--keep DIR] [--repeat R] [--threads T] [FILE...]\n";
      return 0;
    } else {
      files.push_back(a);
    }
  }
  std::unique_ptr<tbb::global_control> limit;
  if (threads > 0) limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);

  const fs::path temp = keep.empty() ? fs::temp_directory_path() / ("treeskel-bench-" + std::to_string(::getpid())) : fs::path(keep);
  fs::create_directories(temp);
  std::vector<std::pair<std::string, std::string>> inputs;  // label, path
  for (std::size_t n : synthetic) {
    eval::GrowOptions grow;
    grow.seed = 7;
    eval::SurfaceSampling sampling;
    sampling.points = n;
    sampling.seed = 7;
    sampling.noise = 0.002;
    PointCloud cloud = eval::sample_cylinders(eval::grow_tree(grow).cylinders, sampling);
    recentre_offset(cloud);
    const fs::path path = temp / ("synthetic_" + std::to_string(n) + ".ply");
    io::write_point_cloud(path, cloud);
    inputs.emplace_back("synthetic tree, binary PLY", path.string());
  }
  for (const auto& f : files) inputs.emplace_back(fs::path(f).filename().string(), f);

  std::cout << "| cloud | points | read (s) | skeleton (s) | points/s | peak memory (MB) | slowest stage |\n"
            << "|---|---:|---:|---:|---:|---:|---|\n";
  std::vector<std::pair<std::size_t, double>> synthetic_times;
  for (const auto& [label, path] : inputs) {
    int pipe_fd[2];
    if (::pipe(pipe_fd) != 0) return 1;
    const pid_t pid = ::fork();
    if (pid == 0) {
      ::close(pipe_fd[0]);
      std::string line;
      try {
        line = measure(path, repeat);
      } catch (const std::exception& e) {
        line = nlohmann::json{{"error", e.what()}}.dump();
      }
      if (::write(pipe_fd[1], line.data(), line.size()) < 0) _exit(2);
      _exit(0);
    }
    ::close(pipe_fd[1]);
    std::string text;
    char buffer[4096];
    for (ssize_t got; (got = ::read(pipe_fd[0], buffer, sizeof buffer)) > 0;) text.append(buffer, static_cast<std::size_t>(got));
    ::close(pipe_fd[0]);
    int status = 0;
    struct rusage usage {};
    ::wait4(pid, &status, 0, &usage);
    const auto j = nlohmann::json::parse(text.empty() ? "{\"error\":\"the child died\"}" : text);
    if (j.contains("error")) {
      std::cout << "| " << label << " | error: " << j["error"].get<std::string>() << " | | | | | |\n";
      continue;
    }
    const double total = j["read"].get<double>() + j["skeleton"].get<double>();
    const auto points = j["points"].get<std::size_t>();
    char row[512];
    std::snprintf(row, sizeof row, "| %s | %zu | %.3f | %.3f | %.0f | %.0f | %s (%.0f%%) |\n", label.c_str(), points,
                  j["read"].get<double>(), j["skeleton"].get<double>(), points / total, usage.ru_maxrss / 1024.0,
                  j["slowest"].get<std::string>().c_str(), 100.0 * j["slowest_share"].get<double>());
    std::cout << row << std::flush;
    if (label.rfind("synthetic", 0) == 0) synthetic_times.emplace_back(points, total);
  }
  if (synthetic_times.size() >= 2) {
    const auto [n0, t0] = synthetic_times[synthetic_times.size() - 2];
    const auto [n1, t1] = synthetic_times.back();
    const double nlogn = (n1 * std::log(double(n1))) / (n0 * std::log(double(n0)));
    std::printf("\nFrom %zu to %zu points the time grows %.2fx; N log N would grow %.2fx.\n", n0, n1, t1 / t0, nlogn);
  }
  if (keep.empty()) fs::remove_all(temp);
  return 0;
}
