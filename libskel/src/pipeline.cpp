#include "treeskel/pipeline.h"

#include "treeskel/error.h"

#include <algorithm>
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
  const OctreeCells cells = partition_octree(cloud, options.octree);  // the sizes need no medians
  SkeletonOptions o = options;
  o.octree.depth = cells.depth;
  o.octree.cube_scale = cells.cube_scale;
  o.level_sets.band_width = band_width_for(options.level_sets, cells);
  o.prune.min_length = prune_length_for(options.prune, o.level_sets.band_width);
  o.graph.bridge_distance = bridge_distance_for(options.graph, cells);
  o.root.slice = root_slice_for(options.root, cells);
  return o;
}

namespace {

/// The stages after the octree, on a cloud whose points are all at distinct places.
Skeleton skeleton_from_cells(const PointCloud& cloud, const OctreeCells& cells, const SkeletonOptions& options,
                             SkeletonStats& stats, StageClock& clock);

}  // namespace

Skeleton extract_skeleton(const PointCloud& cloud, const SkeletonOptions& options, SkeletonStats* stats_out) {
  check_cloud(cloud, options);
  SkeletonStats stats;
  stats.points = cloud.size();
  StageClock clock(options.progress, stats);
  clock.start("octree", 0.0);
  OctreeCells cells = partition_octree(cloud, options.octree);
  if (cells.repeats.empty()) {
    compute_cell_medians(cells, cloud, options.octree.median);
    Skeleton skeleton = skeleton_from_cells(cloud, cells, options, stats, clock);
    if (stats_out) *stats_out = std::move(stats);
    return skeleton;
  }
  // Points repeated at the very same place (merged scans, files written twice) would weigh twice in
  // every count the method makes: the skeleton is extracted from the distinct points, and each
  // repeat then goes where its first copy went. The octree found the repeats.
  const std::size_t n = cloud.size();
  std::vector<std::uint32_t> first(n);  // per point: the first (lowest index) point at its place
  for (std::size_t i = 0; i < n; ++i) first[i] = static_cast<std::uint32_t>(i);
  for (const auto& [point, at] : cells.repeats) first[point] = at;
  PointCloud distinct;
  distinct.offset = cloud.offset;
  std::vector<std::uint32_t> id(n, 0);  // per first point: its index in `distinct`
  for (std::size_t i = 0; i < n; ++i) {
    if (first[i] != i) continue;
    id[i] = static_cast<std::uint32_t>(distinct.positions.size());
    append_point(distinct, cloud, i);
  }
  if (distinct.size() < options.min_points)
    throw InputError("the cloud has " + std::to_string(distinct.size()) + " distinct points; the method needs at least " +
                     std::to_string(options.min_points));
  cells = build_octree_cells(distinct, options.octree);
  Skeleton skeleton = skeleton_from_cells(distinct, cells, options, stats, clock);
  // Back to the input's indices: every point goes where its first copy went.
  std::vector<std::vector<std::uint32_t>> copies(distinct.size());
  for (std::size_t i = 0; i < n; ++i) copies[id[first[i]]].push_back(static_cast<std::uint32_t>(i));
  auto expand = [&](std::vector<std::uint32_t>& points) {
    std::vector<std::uint32_t> all;
    for (std::uint32_t p : points) all.insert(all.end(), copies[p].begin(), copies[p].end());
    std::sort(all.begin(), all.end());
    points = std::move(all);
  };
  for (NodeId v = 0; v < skeleton.node_count(); ++v) expand(skeleton[v].points);
  expand(skeleton.noise_points);
  if (stats_out) *stats_out = std::move(stats);
  return skeleton;
}

namespace {

Skeleton skeleton_from_cells(const PointCloud& cloud, const OctreeCells& cells, const SkeletonOptions& options,
                             SkeletonStats& stats, StageClock& clock) {
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
  skeleton.left_out.outliers = cells.outliers.size();
  stats.band_width = band_width_for(options.level_sets, cells);
  stats.level_set_nodes = skeleton.node_count();
  if (skeleton.node_count() < 2)
    throw InputError("the cloud yields a single skeleton node (octree cell size " + std::to_string(cells.cell_size) +
                     "); it is too small or too sparse for a skeleton");

  if (options.use_prune) {
    clock.start("pruning", 0.6);
    stats.pruned_branches = prune_short_branches(skeleton, stats.band_width, options.prune, &cloud);
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
  if (options.use_prune) stats.pruned_branches += prune_spurs_at_close_forks(skeleton, stats.band_width, options.prune);
  if (options.use_smooth) {
    clock.start("smoothing", 0.95);
    skeleton = smooth_skeleton(std::move(skeleton), options.smooth);
  }
  clock.stop();
  if (options.progress) options.progress("done", 1.0);
  return skeleton;
}

}  // namespace

}  // namespace treeskel
