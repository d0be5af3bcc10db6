// Speed and peak memory of reading a cloud and extracting its skeleton.
//
//   bench_speed [--synthetic N,N,...] [--dense N,N,...] [--noise S] [--keep DIR] [--repeat R] [--threads T]
//               [--depth-steps N] [--prune-point-radius F] [FILE...]
//
// --depth-steps sets OctreeOptions::depth_steps (1: whole octree depths only), to compare;
// --prune-point-radius sets PruneOptions::point_host_factor (0: spurs judged on the nodes' radii).
//
// Synthetic clouds are random trees (eval::grow_tree) sampled with N points (Gaussian noise of
// standard deviation S along the bark's normal, 2 mm by default) and written as binary
// PLY to a temporary folder (or DIR, kept) first. `--dense` clouds are like a terrestrial scan of a
// large tree: thick limbs (a 0.5 m trunk, 10 limbs, 3 orders) sampled evenly with 0.5 mm of noise,
// so that a million points fill about three times the octree cells of the `--synthetic` tree;
// the cell count, not the point count, drives the graph stages. Their generation is not timed.
// Each input then runs in a child process of its own, so that its peak resident memory (from wait4)
// is its own. Prints a Markdown table: the time to read the file, the time to extract the skeleton
// in the first run (as a command meets it: every page of memory touched for the first time) and
// the best of R runs, the points per second of reading and the best run together, the peak memory,
// and the slowest stage.
#include "huge_pages.h"
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

std::string measure(const std::string& path, int repeat, const SkeletonOptions& options) {
  const double t0 = now();
  const PointCloud cloud = io::read_point_cloud(path);
  const double read = now() - t0;
  double best = 1e300, first = 0.0;
  SkeletonStats stats;
  Skeleton skeleton;
  for (int r = 0; r < repeat; ++r) {
    const double t1 = now();
    skeleton = extract_skeleton(cloud, options, &stats);
    const double took = now() - t1;
    if (r == 0) first = took;
    best = std::min(best, took);
  }
  std::string slowest;
  double slowest_s = -1.0;
  for (const auto& [stage, s] : stats.seconds)
    if (s > slowest_s) slowest_s = s, slowest = stage;
  nlohmann::json j;
  j["points"] = cloud.size();
  j["read"] = read;
  j["skeleton"] = best;
  j["first"] = first;
  j["nodes"] = skeleton.node_count();
  j["cells"] = stats.cells;
  j["slowest"] = slowest;
  j["slowest_share"] = slowest_s / best;
  return j.dump();
}

}  // namespace

int main(int argc, char** argv) {
  treeskel::cli::restart_with_huge_pages(argv);  // memory as the command-line tool has it
  std::vector<std::string> files;
  std::vector<std::size_t> synthetic, dense;
  int repeat = 3;
  unsigned threads = 0;
  double noise = 0.002;
  std::string keep;
  SkeletonOptions options;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if ((a == "--synthetic" || a == "--dense") && i + 1 < argc) {
      std::stringstream list(argv[++i]);
      for (std::string n; std::getline(list, n, ',');) (a == "--dense" ? dense : synthetic).push_back(std::stoull(n));
    } else if (a == "--noise" && i + 1 < argc) {
      noise = std::atof(argv[++i]);
    } else if (a == "--keep" && i + 1 < argc) {
      keep = argv[++i];
    } else if (a == "--repeat" && i + 1 < argc) {
      repeat = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--prune-point-radius" && i + 1 < argc) {
      options.prune.point_host_factor = std::atof(argv[++i]);
    } else if (a == "--depth-steps" && i + 1 < argc) {
      options.octree.depth_steps = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--threads" && i + 1 < argc) {
      threads = static_cast<unsigned>(std::atoi(argv[++i]));
    } else if (a == "--help" || a == "-h") {
      std::cout << "usage: bench_speed [--synthetic N,N,...] [--dense N,N,...] [--noise S] [--keep DIR] [--repeat R] [--threads T] [--depth-steps N] [--prune-point-radius F] [FILE...]\n";
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
  auto make = [&](std::size_t n, bool dense) {
    eval::GrowOptions grow;
    grow.seed = 7;
    if (dense) {
      grow.trunk_radius = 0.5;
      grow.branches = 10;
      grow.length_ratio = 0.7;
    }
    eval::SurfaceSampling sampling;
    sampling.points = n;
    sampling.seed = 7;
    sampling.noise = dense ? 0.0005 : noise;
    const fs::path path = temp / ((dense ? "dense_" : "synthetic_") + std::to_string(n) + ".ply");
    // Made in a child process: the memory the cloud took stays with this process otherwise (the
    // allocator keeps what is freed), and every measuring child forked from it would count it.
    const pid_t pid = ::fork();
    if (pid == 0) {
      PointCloud cloud = eval::sample_cylinders(eval::grow_tree(grow).cylinders, sampling);
      recentre_offset(cloud);
      io::write_point_cloud(path, cloud);
      _exit(0);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      std::cerr << "bench_speed: could not make " << path << "\n";
      std::exit(1);
    }
    inputs.emplace_back(dense ? "dense tree, binary PLY" : "synthetic tree, binary PLY", path.string());
  };
  for (std::size_t n : synthetic) make(n, false);
  for (std::size_t n : dense) make(n, true);
  for (const auto& f : files) inputs.emplace_back(fs::path(f).filename().string(), f);

  std::cout << "| cloud | points | read (s) | skeleton, first run (s) | skeleton (s) | points/s | peak memory (MB) | slowest stage |\n"
            << "|---|---:|---:|---:|---:|---:|---:|---|\n";
  std::vector<std::pair<std::size_t, double>> synthetic_times;
  for (const auto& [label, path] : inputs) {
    int pipe_fd[2];
    if (::pipe(pipe_fd) != 0) return 1;
    const pid_t pid = ::fork();
    if (pid == 0) {
      ::close(pipe_fd[0]);
      std::string line;
      try {
        line = measure(path, repeat, options);
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
      std::cout << "| " << label << " | error: " << j["error"].get<std::string>() << " | | | | | | |\n";
      continue;
    }
    const double total = j["read"].get<double>() + j["skeleton"].get<double>();
    const auto points = j["points"].get<std::size_t>();
    char row[512];
    std::snprintf(row, sizeof row, "| %s | %zu | %.3f | %.3f | %.3f | %.0f | %.0f | %s (%.0f%%) |\n", label.c_str(), points,
                  j["read"].get<double>(), j["first"].get<double>(), j["skeleton"].get<double>(), points / total, usage.ru_maxrss / 1024.0,
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
