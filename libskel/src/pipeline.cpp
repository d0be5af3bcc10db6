#include "treeskel/pipeline.h"

#include "treeskel/error.h"

#include <chrono>

namespace treeskel {

namespace {

class StageClock {
public:
  StageClock(const ProgressFn& progress, SkeletonStats& stats) : progress_(progress), stats_(stats) {}
  /// Starts `stage`, which begins at share `done` of the work.
  void start(const std::string& stage, double done) {
    stop();
    stage_ = stage;
    begin_ = std::chrono::steady_clock::now();
    if (progress_) progress_(stage, done);
  }
  void stop() {
    if (stage_.empty()) return;
    const auto now = std::chrono::steady_clock::now();
    stats_.seconds.emplace_back(stage_, std::chrono::duration<double>(now - begin_).count());
    stage_.clear();
  }

private:
  const ProgressFn& progress_;
  SkeletonStats& stats_;
  std::string stage_;
  std::chrono::steady_clock::time_point begin_;
};

void check_cloud(const PointCloud& cloud, const SkeletonOptions& options) {
  const auto n = std::to_string(cloud.size());
  switch (classify_shape(cloud)) {
    case CloudShape::empty:
      throw InputError("the point cloud is empty");
    case CloudShape::identical:
      throw InputError("all " + n + " points are at the same place");
    case CloudShape::collinear:
      throw InputError("all " + n + " points lie on one straight line; a tree needs a 3D cloud");
    case CloudShape::ok:
      break;
  }
  if (cloud.size() < options.min_points)
    throw InputError("the cloud has " + n + " points; the method needs at least " +
                     std::to_string(options.min_points));
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (!cloud.positions[i].allFinite())
      throw InputError("point " + std::to_string(i) + " has a coordinate that is not a finite number");
}

}  // namespace

SkeletonOptions automatic_options(const PointCloud& cloud, const SkeletonOptions& options) {
  check_cloud(cloud, options);
  const OctreeCells cells = build_octree_cells(cloud, options.octree);
  SkeletonOptions o = options;
  o.octree.depth = cells.depth;
  o.level_sets.band_width = band_width_for(options.level_sets, cells);
  o.prune.min_length = prune_length_for(options.prune, o.level_sets.band_width);
  o.graph.bridge_distance = bridge_distance_for(options.graph, cells);
  o.root.slice = root_slice_for(options.root, cells);
  return o;
}

Skeleton extract_skeleton(const PointCloud& cloud, const SkeletonOptions& options, SkeletonStats* stats_out) {
  check_cloud(cloud, options);
  SkeletonStats stats;
  stats.points = cloud.size();
  StageClock clock(options.progress, stats);

  clock.start("octree", 0.0);
  const OctreeCells cells = build_octree_cells(cloud, options.octree);
  stats.octree_depth = cells.depth;
  stats.cell_size = cells.cell_size;
  stats.cells = cells.cell_count();

  clock.start("neighbour graph", 0.25);
  const CellGraph graph = build_neighbour_graph(cells, options.graph);
  stats.graph_edges = graph.edge_count();
  stats.bridges = graph.bridges;
  const MainPart main = select_main_part(cells, graph, options.graph);
  stats.parts = main.parts;

  clock.start("geodesic distance", 0.4);
  const auto roots = select_root_cells(cells, graph, main.in_tree, options.root);
  const GeodesicField geodesic = geodesic_distance(graph, roots);

  clock.start("level sets", 0.5);
  Skeleton skeleton = level_set_skeleton(cloud, cells, graph, main.in_tree, geodesic, options.level_sets);
  skeleton.left_out = main.left_out;
  stats.band_width = band_width_for(options.level_sets, cells);
  stats.level_set_nodes = skeleton.node_count();
  if (skeleton.node_count() < 2)
    throw InputError("the cloud yields a single skeleton node (octree cell size " + std::to_string(cells.cell_size) +
                     "); it is too small or too sparse for a skeleton");

  if (options.use_prune) {
    clock.start("pruning", 0.6);
    stats.pruned_branches = prune_short_branches(skeleton, stats.band_width, options.prune);
  }
  if (options.use_cpc) {
    clock.start("CPC", 0.65);
    recentre_nodes(skeleton, cloud, options.cpc);
  }
  if (options.use_refine) {
    clock.start("refinement", 0.85);
    RefineOptions refine = options.refine;
    refine.cpc = options.use_cpc ? options.cpc : CpcOptions{0.0};
    stats.refined_splits = refine_topology(skeleton, cloud, refine);
  }
  if (options.use_junctions) {
    clock.start("fork placement", 0.9);
    stats.forks_moved = relocate_forks(skeleton, stats.band_width, options.junctions);
  }
  if (options.use_smooth) {
    clock.start("smoothing", 0.95);
    skeleton = smooth_skeleton(skeleton, options.smooth);
  }
  clock.stop();
  if (options.progress) options.progress("done", 1.0);
  if (stats_out) *stats_out = std::move(stats);
  return skeleton;
}

}  // namespace treeskel
