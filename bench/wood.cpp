// Wood and leaves (forest::separate_wood) scored against the truth: on each tree of the synthetic
// plots (its wood and leaf points, as `--wood-only` meets it in `treeskel plot`), and on clouds given
// on the command line: a text cloud whose fourth column is labelled `foliage` in its header (0 wood,
// 1 or more leaves, as arbor's) is scored, any other cloud gets the share it calls leaves (on a
// leafless tree, every one of them is wood called a leaf). For a labelled cloud it also extracts the
// skeleton (default options) of its labelled wood, of the wood this rule keeps and of the whole leafy
// cloud, and gives the SPD of the latter two against the first, both ways, over the cloud's longest side.
// Usage: bench_wood [--seeds N] [--threshold T] [--ways-weight W] [--ways-reference N] [--join N] [CLOUD...]   (results in docs/plots.md)
#include "treeskel/eval/metrics.h"
#include "treeskel/eval/plots.h"
#include "treeskel/forest/wood.h"
#include "treeskel/io/point_cloud_io.h"
#include "treeskel/pipeline.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace treeskel;

struct Tally {
  std::size_t wood_as_wood = 0, wood_as_leaf = 0, leaf_as_wood = 0, leaf_as_leaf = 0;
  void add(bool truly_wood, bool called_wood) {
    (truly_wood ? (called_wood ? wood_as_wood : wood_as_leaf) : (called_wood ? leaf_as_wood : leaf_as_leaf))++;
  }
  static double ratio(std::size_t a, std::size_t b) { return a + b ? static_cast<double>(a) / static_cast<double>(a + b) : 0.0; }
  double recall() const { return ratio(wood_as_wood, wood_as_leaf); }
  double precision() const { return ratio(wood_as_wood, leaf_as_wood); }
  double leaf_recall() const { return ratio(leaf_as_leaf, leaf_as_wood); }
  double balanced() const { return 0.5 * (recall() + leaf_recall()); }
};

/// A text cloud with a `foliage` column in its `#` header: positions and wood flags; false if it has none.
bool read_labelled(const std::string& file, PointCloud& cloud, std::vector<std::uint8_t>& wood) {
  std::ifstream in(file);
  std::string line;
  if (!std::getline(in, line) || line.find("foliage") == std::string::npos) return false;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream row(line);
    double x, y, z, label;
    if (!(row >> x >> y >> z >> label)) continue;
    cloud.positions.emplace_back(x, y, z);
    wood.push_back(label == 0);
  }
  recentre_offset(cloud);
  return true;
}

/// `x` with three decimals.
std::string fixed(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", x);
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 3;
  forest::WoodOptions options;
  std::vector<std::string> clouds;
  struct Labelled {
    std::string file;
    PointCloud cloud;
    std::vector<std::uint8_t> truth, kept;
  };
  std::vector<Labelled> skeletons;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--seeds") && i + 1 < argc) seeds = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--threshold") && i + 1 < argc) options.threshold = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--ways-weight") && i + 1 < argc) options.ways_weight = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--ways-reference") && i + 1 < argc) options.ways_reference = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--join") && i + 1 < argc) options.join_parts = static_cast<std::size_t>(std::atol(argv[++i]));
    else if (argv[i][0] == '-') {
      std::fprintf(stderr, "usage: bench_wood [--seeds N] [--threshold T] [--ways-weight W] [--ways-reference N] [--join N] [CLOUD...]\n");
      return 2;
    } else clouds.push_back(argv[i]);
  }
  // "estimated": forest::estimate_leaf_share, what the leafy warning compares with kLeafyShare.
  std::printf("| cloud | points | truth: leaves | called leaves | estimated | wood recall | wood precision | leaf recall | balanced accuracy | seconds |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  auto row = [](const std::string& name, std::size_t points, const Tally* t, double called_leaves, const std::string& estimated,
                double seconds) {
    if (t)
      std::printf("| %s | %zu | %.3f | %.3f | %s | %.3f | %.3f | %.3f | %.3f | %.2f |\n", name.c_str(), points,
                  Tally::ratio(t->leaf_as_leaf + t->leaf_as_wood, t->wood_as_wood + t->wood_as_leaf), called_leaves,
                  estimated.c_str(), t->recall(), t->precision(), t->leaf_recall(), t->balanced(), seconds);
    else
      std::printf("| %s | %zu | | %.3f | %s | | | | | %.2f |\n", name.c_str(), points, called_leaves, estimated.c_str(), seconds);
    std::fflush(stdout);
  };
  double balanced_sum = 0;
  for (int seed = 1; seed <= seeds; ++seed) {
    eval::PlotOptions o;
    o.seed = static_cast<std::uint64_t>(seed);
    const eval::SyntheticPlot plot = eval::make_plot(o);
    Tally all;
    std::size_t points = 0, called = 0;
    double seconds = 0, least = 1, most = 0;
    for (std::size_t t = 1; t <= plot.stems.size(); ++t) {
      PointCloud tree;
      std::vector<std::uint8_t> wood;
      for (std::size_t p = 0; p < plot.cloud.size(); ++p)
        if (plot.tree[p] == t) {
          tree.positions.push_back(plot.cloud.positions[p]);
          wood.push_back(plot.kind[p] == eval::PointKind::wood);
        }
      const auto start = std::chrono::steady_clock::now();
      const forest::WoodLeaf w = forest::separate_wood(tree, options);
      seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      for (std::size_t p = 0; p < tree.size(); ++p) all.add(wood[p], w.is_wood[p]);
      if (seed == 1) skeletons.push_back({"synthetic plot 1, tree " + std::to_string(t), tree, wood, w.is_wood});
      points += tree.size();
      called += w.leaf_points;
      const double estimate = forest::estimate_leaf_share(tree);
      least = std::min(least, estimate);
      most = std::max(most, estimate);
    }
    row("synthetic plot " + std::to_string(seed) + ", each tree", points, &all, static_cast<double>(called) / static_cast<double>(points),
        fixed(least) + "-" + fixed(most), seconds);
    balanced_sum += all.balanced();
  }
  if (seeds > 0) std::printf("| synthetic plots, mean balanced accuracy | | | | | | | | %.3f | |\n", balanced_sum / seeds);
  for (const auto& file : clouds) {
    PointCloud cloud;
    std::vector<std::uint8_t> wood;
    const bool labelled = read_labelled(file, cloud, wood);
    if (!labelled) cloud = io::read_point_cloud(file);
    const auto start = std::chrono::steady_clock::now();
    const forest::WoodLeaf w = forest::separate_wood(cloud, options);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    Tally t;
    if (labelled)
      for (std::size_t p = 0; p < cloud.size(); ++p) t.add(wood[p], w.is_wood[p]);
    row(std::filesystem::path(file).filename().string(), cloud.size(), labelled ? &t : nullptr, w.leaf_share(),
        fixed(forest::estimate_leaf_share(cloud)), seconds);
    if (labelled) skeletons.push_back({file, cloud, wood, w.is_wood});
  }
  if (skeletons.empty()) return 0;
  std::printf("\n| cloud | skeleton of | nodes | SPD to the labelled wood's | SPD from it | (over the longest side) |\n|---|---|---:|---:|---:|---|\n");
  for (const auto& l : skeletons) {
    const double side = bounding_box(l.cloud).sizes().maxCoeff();
    const Skeleton reference = extract_skeleton(forest::select_points(l.cloud, l.truth, 1));
    const std::string name = l.file.rfind("synthetic", 0) == 0 ? l.file : std::filesystem::path(l.file).filename().string();
    std::printf("| %s | the labelled wood | %zu | | | |\n", name.c_str(), reference.node_count());
    for (const auto& [what, s] : {std::pair<const char*, Skeleton>{"the wood kept (--wood-only)", extract_skeleton(forest::select_points(l.cloud, l.kept, 1))},
                                  {"the whole cloud", extract_skeleton(l.cloud)}}) {
      std::printf("| %s | %s | %zu | %.4f | %.4f | |\n", name.c_str(), what, s.node_count(),
                  eval::skeleton_point_deviation(s, reference) / side, eval::skeleton_point_deviation(reference, s) / side);
    }
  }
  return 0;
}
