// The plot segmentation on synthetic plots with the truth per point: stems found (precision and recall
// at 0.5 m in plan) and the mean IoU of each true tree's points with its found tree, per seed, for the
// defaults of `treeskel plot`. Usage: bench_plots [--seeds N] [--trees N] [--write DIR] [--voxel V]
// (--write saves each plot as DIR/plot_SEED.ply with its true tree and kind per point).
#include "treeskel/eval/plots.h"
#include "treeskel/forest/ground.h"
#include "treeskel/forest/segment.h"
#include "treeskel/forest/stems.h"
#include "treeskel/io/point_cloud_io.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

int main(int argc, char** argv) {
  using namespace treeskel;
  int seeds = 3, trees = 8;
  std::string write;
  treeskel::forest::SegmentOptions segment;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--seeds")) seeds = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--trees")) trees = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--write")) write = argv[i + 1];
    else if (!std::strcmp(argv[i], "--voxel")) segment.voxel = std::atof(argv[i + 1]);
    else {
      std::fprintf(stderr, "usage: bench_plots [--seeds N] [--trees N] [--write DIR] [--voxel V]\n");
      return 2;
    }
  }
  std::printf("| seed | points | true stems | found | stem precision | stem recall | mean IoU | tree points elsewhere | in no tree | ground and understorey in trees | ground found / true | seconds |\n");
  std::printf("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  double sum_p = 0, sum_r = 0, sum_iou = 0;
  for (int seed = 1; seed <= seeds; ++seed) {
    eval::PlotOptions o;
    o.seed = static_cast<std::uint64_t>(seed);
    o.trees = trees;
    const eval::SyntheticPlot plot = eval::make_plot(o);
    if (!write.empty()) {
      std::filesystem::create_directories(write);
      io::CloudWriteOptions w;
      w.fields = {{"tree_id", io::PointField::Type::uint32, {}}, {"kind", io::PointField::Type::uint8, {}}};
      for (std::size_t p = 0; p < plot.cloud.size(); ++p) {
        w.fields[0].values.push_back(plot.tree[p]);
        w.fields[1].values.push_back(static_cast<double>(plot.kind[p]));
      }
      io::write_point_cloud(std::filesystem::path(write) / ("plot_" + std::to_string(seed) + ".ply"), plot.cloud, w);
    }
    const auto start = std::chrono::steady_clock::now();
    const forest::Ground ground = forest::classify_ground(plot.cloud);
    const auto stems = forest::find_stems(plot.cloud, ground);
    const forest::Segmentation seg = forest::segment_trees(plot.cloud, ground, stems, {}, segment);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::vector<Eigen::Vector2d> centres;
    for (const auto& s : stems) centres.push_back(s.centre);
    const eval::PlotScore score = eval::score_plot(plot, centres, seg.tree);
    std::size_t true_ground = 0, found_true_ground = 0;
    for (std::size_t p = 0; p < plot.cloud.size(); ++p)
      if (plot.kind[p] == eval::PointKind::ground) {
        ++true_ground;
        found_true_ground += ground.is_ground[p];
      }
    std::printf("| %d | %zu | %zu | %zu | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %zu / %zu | %.2f |\n", seed, plot.cloud.size(),
                score.true_stems, score.found_stems, score.stem_precision, score.stem_recall, score.mean_iou,
                score.tree_points_elsewhere, score.tree_points_unassigned, score.others_in_trees, found_true_ground, true_ground, seconds);
    sum_p += score.stem_precision;
    sum_r += score.stem_recall;
    sum_iou += score.mean_iou;
  }
  std::printf("| mean | | | | %.3f | %.3f | %.3f | | | | | |\n", sum_p / seeds, sum_r / seeds, sum_iou / seeds);
  return 0;
}
