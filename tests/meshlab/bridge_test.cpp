#include "bridge.h"

#include "support/synthetic.h"
#include "treeskel/io/point_cloud_io.h"
#include "treeskel/modeling/radii.h"
#include "treeskel/modeling/sweep.h"
#include "treeskel/pipeline.h"

#include <Eigen/Core>
#include <gtest/gtest.h>

#include <array>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

namespace treeskel::meshlab {
namespace {

/// A bundled cloud as the plugin passes it, flat: at its world coordinates, or `near_origin` (its
/// minimum corner at 0, in floats), as a georeferenced cloud must be before MeshLab reads it.
std::vector<double> flat_cloud(const std::string& name, bool near_origin = false) {
  const PointCloud cloud = io::read_point_cloud(test::data_file(name));
  std::vector<double> xyz;
  for (const auto& p : cloud.positions)
    for (int a = 0; a < 3; ++a)
      xyz.push_back(near_origin ? static_cast<double>(static_cast<float>(p[a])) : p[a] + cloud.offset[a]);
  return xyz;
}

/// The bundled cloud near the origin.
std::vector<double> near_origin(const std::string& name) { return flat_cloud(name, true); }

/// True when `edges` (index pairs) over `nodes` nodes form one tree.
bool is_tree(std::size_t nodes, const std::vector<int>& edges) {
  SkeletonGraph graph(nodes);
  for (std::size_t e = 0; e + 1 < edges.size(); e += 2) {
    if (edges[e] < 0 || edges[e + 1] < 0 || static_cast<std::size_t>(std::max(edges[e], edges[e + 1])) >= nodes)
      return false;
    boost::add_edge(static_cast<NodeId>(edges[e]), static_cast<NodeId>(edges[e + 1]), graph);
  }
  return treeskel::is_tree(graph);
}

/// True when every directed edge of the triangles appears once and its reverse once: closed, manifold
/// along edges and consistently oriented.
bool closed_and_oriented(const std::vector<int>& triangles) {
  std::map<std::pair<int, int>, int> directed;
  for (std::size_t t = 0; t < triangles.size(); t += 3)
    for (int k = 0; k < 3; ++k) ++directed[{triangles[t + k], triangles[t + (k + 1) % 3]}];
  for (const auto& [edge, count] : directed) {
    if (count != 1) return false;
    const auto reverse = directed.find({edge.second, edge.first});
    if (reverse == directed.end() || reverse->second != 1) return false;
  }
  return !triangles.empty();
}

std::vector<int> percents;
bool record(const int percent, const char*) {
  percents.push_back(percent);
  return true;
}

TEST(MeshlabBridge, DefaultsAreTheLibrarysWithAutomaticScales) {
  const SkeletonParams p = default_skeleton_params();
  const SkeletonOptions o;
  EXPECT_EQ(p.octree_depth, 0);
  EXPECT_EQ(p.band_width, 0.0);
  EXPECT_EQ(p.prune_length, 0.0);
  EXPECT_EQ(p.bridge_distance, 0.0);
  EXPECT_EQ(p.points_per_cell, o.octree.points_per_cell);
  EXPECT_EQ(p.cpc_weight, o.cpc.weight);
  EXPECT_EQ(p.samples, o.smooth.samples_per_edge);
  EXPECT_EQ(p.up[2], 1.0);
  const ModelParams m = default_model_params();
  EXPECT_EQ(m.exponent, 2.0);
  EXPECT_GT(m.segments, m.min_segments);
  EXPECT_TRUE(m.repair);
  EXPECT_FALSE(m.allow_defects);
  EXPECT_EQ(m.complete, modeling::RadiusOptions{}.complete);
  EXPECT_EQ(m.complete_all, modeling::RadiusOptions{}.completion.tufts_and_bushes);
}

TEST(MeshlabBridge, ResolvedScalesAreTheLibrarysAndGiveTheSameSkeleton) {
  const std::vector<double> xyz = flat_cloud("tree_rtwig.txt");
  SkeletonParams resolved = default_skeleton_params();
  std::string error;
  ASSERT_TRUE(resolve_scales(xyz, resolved, error)) << error;
  EXPECT_EQ(resolved.octree_depth, 0);  // automatic: the cells may lie between two depths' sizes
  EXPECT_GT(resolved.band_width, 0.0);
  EXPECT_EQ(resolved.prune_length, 0.5 * resolved.band_width);  // skeletonize's shortest branch
  SkeletonParams for_mesh = default_skeleton_params();
  ASSERT_TRUE(resolve_scales(xyz, for_mesh, error, true)) << error;
  EXPECT_EQ(for_mesh.prune_length, for_mesh.band_width);  // a model's
  EXPECT_DOUBLE_EQ(resolved.bridge_distance, 2.0 * resolved.band_width);

  const ModelParams model = default_model_params();
  SkeletonLayer automatic, spelled_out;
  ASSERT_TRUE(tree_skeleton(xyz, default_skeleton_params(), model, nullptr, automatic, error)) << error;
  ASSERT_TRUE(tree_skeleton(xyz, resolved, model, nullptr, spelled_out, error)) << error;
  EXPECT_EQ(automatic.xyz, spelled_out.xyz);
  EXPECT_EQ(automatic.edges, spelled_out.edges);
}

TEST(MeshlabBridge, SkeletonLayerIsATreeWithPositiveRadiiInTheCloudsFrame) {
  const std::vector<double> xyz = flat_cloud("tree_adtree1.xyz");
  SkeletonLayer layer;
  std::string error;
  percents.clear();
  ASSERT_TRUE(tree_skeleton(xyz, default_skeleton_params(), default_model_params(), record, layer, error)) << error;
  const std::size_t nodes = layer.radius.size();
  ASSERT_EQ(layer.xyz.size(), 3 * nodes);
  EXPECT_GT(nodes, 100u);
  EXPECT_TRUE(is_tree(nodes, layer.edges));
  for (double r : layer.radius) EXPECT_GT(r, 0.0);
  // Nodes lie within the cloud's box (world coordinates, not the library's local frame), but for the
  // little a smoothing spline may overshoot a tip: 2% of the box's diagonal.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (std::size_t i = 0; i < xyz.size(); i += 3)
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], xyz[i + a]), hi[a] = std::max(hi[a], xyz[i + a]);
  const double slack = 0.02 * (hi - lo).norm();
  for (std::size_t i = 0; i < layer.xyz.size(); i += 3)
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(layer.xyz[i + a], lo[a] - slack);
      EXPECT_LE(layer.xyz[i + a], hi[a] + slack);
    }
  ASSERT_FALSE(percents.empty());
  EXPECT_TRUE(std::is_sorted(percents.begin(), percents.end()));
  EXPECT_GE(percents.front(), 0);
  EXPECT_EQ(percents.back(), 100);
  EXPECT_NE(layer.summary.find("branch points"), std::string::npos);
}

/// "Grow through missed points" is `model --complete`: the layer holds the skeleton the library
/// completes at the cell size it was extracted with, which has more nodes than the default's.
TEST(MeshlabBridge, CompletionGivesTheLibrarysCompletedSkeleton) {
  const std::vector<double> xyz = flat_cloud("tree_adtree1.xyz");
  ModelParams m = default_model_params();
  m.complete = true;
  SkeletonLayer completed, plain;
  std::string error;
  ASSERT_TRUE(tree_skeleton(xyz, default_skeleton_params(), m, nullptr, completed, error)) << error;
  ASSERT_TRUE(tree_skeleton(xyz, default_skeleton_params(), default_model_params(), nullptr, plain, error)) << error;

  const PointCloud cloud = io::read_point_cloud(test::data_file("tree_adtree1.xyz"));
  SkeletonStats stats;
  Skeleton skeleton = extract_skeleton(cloud, {}, &stats);
  modeling::RadiusOptions radii;
  radii.complete = true;
  radii.cell_size = stats.cell_size;
  modeling::RadiusStats grown;
  modeling::fit_radii(skeleton, &cloud, radii, &grown);
  ASSERT_GT(grown.completion.nodes, 0u);
  EXPECT_EQ(completed.radius.size(), skeleton.node_count());
  EXPECT_EQ(completed.radius.size(), plain.radius.size() + grown.completion.nodes);
  EXPECT_TRUE(is_tree(completed.radius.size(), completed.edges));
}

/// "Grow through missed points" set to every group is `model --complete-all`: the tufts and bushes
/// grow too, so the layer has more nodes than with branches alone, as many as the library gives.
TEST(MeshlabBridge, EveryGroupIsTheLibrarysCompleteAll) {
  const std::vector<double> xyz = flat_cloud("tree_adtree1.xyz");
  ModelParams some = default_model_params(), all = some;
  some.complete = all.complete = true;
  all.complete_all = true;
  SkeletonLayer branches, every;
  std::string error;
  ASSERT_TRUE(tree_skeleton(xyz, default_skeleton_params(), some, nullptr, branches, error)) << error;
  ASSERT_TRUE(tree_skeleton(xyz, default_skeleton_params(), all, nullptr, every, error)) << error;

  const PointCloud cloud = io::read_point_cloud(test::data_file("tree_adtree1.xyz"));
  SkeletonStats stats;
  Skeleton skeleton = extract_skeleton(cloud, {}, &stats);
  modeling::RadiusOptions radii;
  radii.complete = true;
  radii.completion = all_grafts();
  radii.cell_size = stats.cell_size;
  modeling::RadiusStats grown;
  modeling::fit_radii(skeleton, &cloud, radii, &grown);
  EXPECT_FALSE(grown.completion.leafy_bushes);
  EXPECT_EQ(every.radius.size(), skeleton.node_count());
  EXPECT_GT(every.radius.size(), branches.radius.size());
  EXPECT_TRUE(is_tree(every.radius.size(), every.edges));
  for (const auto& w : every.warnings) EXPECT_EQ(w.find("lie in bushes"), std::string::npos) << w;
}

TEST(MeshlabBridge, MeshLayerIsClosedAndOriented) {
  const std::vector<double> xyz = flat_cloud("tree_rtwig.txt");
  MeshLayer layer;
  std::string error;
  percents.clear();
  ASSERT_TRUE(tree_mesh(xyz, default_skeleton_params(), default_model_params(), record, layer, error)) << error;
  EXPECT_GT(layer.triangles.size(), 3000u);
  EXPECT_EQ(layer.triangles.size() % 3, 0u);
  EXPECT_TRUE(closed_and_oriented(layer.triangles));
  // Euler characteristic of a sphere: one closed genus-0 component.
  const long v = static_cast<long>(layer.xyz.size() / 3), f = static_cast<long>(layer.triangles.size() / 3);
  EXPECT_EQ(v - f / 2, 2);
  EXPECT_TRUE(std::is_sorted(percents.begin(), percents.end()));
  EXPECT_EQ(percents.back(), 100);
  EXPECT_NE(layer.summary.find("closed, manifold, no self-intersection"), std::string::npos);
}

// The mesh filter's skeleton is pruned as `treeskel model` prunes (modeling::use_model_pruning), the
// skeleton filter's as `skeletonize` does: the mesh is the library's model of the skeleton pruned at
// one radius, which has more nodes than the skeleton filter's layer.
TEST(MeshlabBridge, MeshFilterPrunesAsTheModelCommand) {
  const std::vector<double> xyz = flat_cloud("tree_adtree1.xyz");
  MeshLayer mesh;
  SkeletonLayer skeleton_layer;
  std::string error;
  ASSERT_TRUE(tree_mesh(xyz, default_skeleton_params(), default_model_params(), nullptr, mesh, error)) << error;
  ASSERT_TRUE(tree_skeleton(xyz, default_skeleton_params(), default_model_params(), nullptr, skeleton_layer, error)) << error;

  const PointCloud cloud = io::read_point_cloud(test::data_file("tree_adtree1.xyz"));
  SkeletonOptions as_model;
  modeling::use_model_pruning(as_model.prune);
  SkeletonStats stats;
  Skeleton skeleton = extract_skeleton(cloud, as_model, &stats);
  EXPECT_GT(skeleton.node_count(), skeleton_layer.radius.size());
  EXPECT_EQ(extract_skeleton(cloud).node_count(), skeleton_layer.radius.size());
  modeling::RadiusOptions radii;
  radii.cell_size = stats.cell_size;
  modeling::fit_radii(skeleton, &cloud, radii);
  EXPECT_EQ(mesh.triangles.size() / 3, modeling::sweep_mesh(skeleton).n_faces());
}

TEST(MeshlabBridge, MeshLayerCarriesTheCommandsWarnings) {
  // The bundled tree at a fifth of its size: 0.74 tall, shorter than breast height.
  std::vector<double> xyz = flat_cloud("tree_rtwig.txt");
  for (double& c : xyz) c *= 0.2;
  MeshLayer layer;
  std::string error;
  ASSERT_TRUE(tree_mesh(xyz, default_skeleton_params(), default_model_params(), nullptr, layer, error)) << error;
  ASSERT_FALSE(layer.warnings.empty());
  EXPECT_NE(layer.warnings.front().find("shorter than breast height"), std::string::npos) << layer.warnings.front();
  // The bundled tree as it is: nothing to warn about.
  MeshLayer plain;
  ASSERT_TRUE(tree_mesh(flat_cloud("tree_rtwig.txt"), default_skeleton_params(), default_model_params(), nullptr, plain, error));
  EXPECT_TRUE(plain.warnings.empty()) << plain.warnings.front();
  // A broadleaf in leaf: said to look leafy, first.
  MeshLayer leafy;
  ASSERT_TRUE(tree_mesh(near_origin("tree_arbor_leafy.xyz"), default_skeleton_params(), default_model_params(), nullptr, leafy, error))
      << error;
  ASSERT_FALSE(leafy.warnings.empty());
  EXPECT_NE(leafy.warnings.front().find("looks leafy"), std::string::npos) << leafy.warnings.front();
  // Its remedy is the filter's own option, not the command line's.
  EXPECT_NE(leafy.warnings.front().find("\"Wood only\""), std::string::npos) << leafy.warnings.front();
  EXPECT_EQ(leafy.warnings.front().find("--wood-only"), std::string::npos) << leafy.warnings.front();
}

/// The number after `before` in `text`, or -1.
long number_after(const std::string& text, const std::string& before) {
  const auto at = text.find(before);
  return at == std::string::npos ? -1 : std::stol(text.substr(at + before.size()));
}

/// "Wood only" makes the skeleton and the mesh of the points that look like wood and hands back the
/// others, in the input's frame, for a layer of their own; the log line counts both. The skeleton
/// filter warns of a leafy cloud as the mesh filter does.
TEST(MeshlabBridge, WoodOnlySetsTheLeavesAsideForALayerOfTheirOwn) {
  const std::vector<double> xyz = near_origin("tree_arbor_leafy.xyz");
  const std::size_t all = xyz.size() / 3;
  std::string error;
  SkeletonLayer leafy;
  ASSERT_TRUE(tree_skeleton(xyz, default_skeleton_params(), default_model_params(), nullptr, leafy, error)) << error;
  ASSERT_EQ(leafy.warnings.size(), 1u);
  EXPECT_NE(leafy.warnings.front().find("looks leafy"), std::string::npos) << leafy.warnings.front();
  EXPECT_TRUE(leafy.wood.empty() && leafy.leaves.empty());

  SkeletonParams wood_only = default_skeleton_params();
  wood_only.wood_only = true;
  SkeletonLayer skeleton;
  ASSERT_TRUE(tree_skeleton(xyz, wood_only, default_model_params(), nullptr, skeleton, error)) << error;
  EXPECT_TRUE(skeleton.warnings.empty()) << skeleton.warnings.front();
  EXPECT_TRUE(is_tree(skeleton.radius.size(), skeleton.edges));
  ASSERT_EQ(skeleton.leaves.size() % 3, 0u);
  const std::size_t leaves = skeleton.leaves.size() / 3;
  EXPECT_GT(leaves, all / 10);  // a broadleaf in leaf (arbor's labels: 28% leaves)
  EXPECT_LT(leaves, all / 2);
  EXPECT_EQ(number_after(skeleton.wood, "wood only: "), static_cast<long>(all - leaves)) << skeleton.wood;
  EXPECT_EQ(number_after(skeleton.wood, "points look like wood; "), static_cast<long>(leaves)) << skeleton.wood;
  // Every point set aside is one of the cloud's, at its coordinates.
  std::set<std::array<double, 3>> input;
  for (std::size_t i = 0; i < xyz.size(); i += 3) input.insert({xyz[i], xyz[i + 1], xyz[i + 2]});
  std::size_t found = 0;
  for (std::size_t i = 0; i < skeleton.leaves.size(); i += 3)
    found += input.count({skeleton.leaves[i], skeleton.leaves[i + 1], skeleton.leaves[i + 2]});
  EXPECT_EQ(found, leaves);

  MeshLayer mesh;
  ASSERT_TRUE(tree_mesh(xyz, wood_only, default_model_params(), nullptr, mesh, error)) << error;
  EXPECT_TRUE(closed_and_oriented(mesh.triangles));
  EXPECT_EQ(mesh.wood, skeleton.wood);
  EXPECT_EQ(mesh.leaves, skeleton.leaves);
  EXPECT_EQ(number_after(mesh.summary, "treeskel: "), static_cast<long>(all - leaves)) << mesh.summary;
  for (const auto& w : mesh.warnings) EXPECT_EQ(w.find("looks leafy"), std::string::npos) << w;
}

TEST(MeshlabBridge, CloudsTheMethodCannotUseAreErrorsNotExceptions) {
  SkeletonLayer skeleton;
  MeshLayer mesh;
  SkeletonParams p = default_skeleton_params();
  const ModelParams m = default_model_params();
  std::string error;
  EXPECT_FALSE(tree_skeleton({}, p, m, nullptr, skeleton, error));
  EXPECT_NE(error.find("empty"), std::string::npos) << error;
  EXPECT_FALSE(tree_mesh({0, 0, 0, 1, 0, 0, 0, 1, 1}, p, m, nullptr, mesh, error));
  EXPECT_NE(error.find("3 points"), std::string::npos) << error;
  EXPECT_FALSE(resolve_scales({0, 0, 0, 1, 0, 0, 0, 1, 1}, p, error));
  EXPECT_EQ(p.band_width, 0.0);  // left automatic
  EXPECT_FALSE(tree_skeleton({1, 2}, p, m, nullptr, skeleton, error));
  p.up[0] = p.up[1] = p.up[2] = 0.0;
  EXPECT_FALSE(tree_skeleton(flat_cloud("tree_rtwig.txt"), p, m, nullptr, skeleton, error));
  EXPECT_NE(error.find("up axis"), std::string::npos) << error;
  EXPECT_TRUE(skeleton.xyz.empty());  // nothing half-filled
}

/// MeshLab holds a cloud as 32-bit floats: at georeferenced coordinates they lie on a grid too coarse
/// for a skeleton (arbor's tree at its UTM northing: 0.5 apart), which is an error that says what to
/// do, not a model of a tree cut in slabs; a grid of a few thousandths of the extent is a warning.
TEST(MeshlabBridge, CloudsFarFromTheOriginAreRefusedOrWarnedAbout) {
  std::vector<double> utm = flat_cloud("tree_arbor_leafy.xyz");
  for (double& c : utm) c = static_cast<double>(static_cast<float>(c));  // as MeshLab holds them
  SkeletonLayer skeleton;
  MeshLayer mesh;
  std::string error;
  EXPECT_FALSE(tree_skeleton(utm, default_skeleton_params(), default_model_params(), nullptr, skeleton, error));
  EXPECT_NE(error.find("32-bit floats are 0.5 apart"), std::string::npos) << error;
  EXPECT_NE(error.find("near the origin"), std::string::npos) << error;
  error.clear();
  EXPECT_FALSE(tree_mesh(utm, default_skeleton_params(), default_model_params(), nullptr, mesh, error));
  EXPECT_NE(error.find("32-bit floats"), std::string::npos) << error;
  EXPECT_TRUE(mesh.triangles.empty());

  // rTwig's tree (about 5 across) moved to x = 10,000: floats 0.00098 apart, a warning only.
  std::vector<double> shifted = flat_cloud("tree_rtwig.txt");
  for (std::size_t i = 0; i < shifted.size(); i += 3) shifted[i] = static_cast<double>(static_cast<float>(shifted[i] + 10000.0));
  ASSERT_TRUE(tree_skeleton(shifted, default_skeleton_params(), default_model_params(), nullptr, skeleton, error)) << error;
  ASSERT_EQ(skeleton.warnings.size(), 1u);
  EXPECT_NE(skeleton.warnings.front().find("32-bit floats are 0.0009766 apart"), std::string::npos) << skeleton.warnings.front();
  // Where it was, nothing to say.
  ASSERT_TRUE(tree_skeleton(flat_cloud("tree_rtwig.txt"), default_skeleton_params(), default_model_params(), nullptr,
                            skeleton, error));
  EXPECT_TRUE(skeleton.warnings.empty()) << skeleton.warnings.front();
}

/// The bundled scripts hold every parameter the filters declare, at the defaults (0 for automatic scales).
TEST(MeshlabBridge, BundledScriptsHoldTheDefaults) {
  const SkeletonParams s = default_skeleton_params();
  const ModelParams m = default_model_params();
  const std::map<std::string, double> expected = {
      {"upAxis", 0},          {"octreeDepth", 0},        {"pointsPerCell", s.points_per_cell},
      {"bandWidth", 0},       {"pruneLength", 0},        {"bridgeDistance", 0},
      {"cpcWeight", s.cpc_weight}, {"eta", s.eta},       {"splineSamples", s.samples},
      {"splineTension", s.tension}, {"exponent", m.exponent}, {"tipWeight", m.tip_weight},
      {"segments", m.segments}, {"minSegments", m.min_segments}, {"minRadius", m.min_radius},
      {"breastHeight", m.breast_height}, {"complete", m.complete ? (m.complete_all ? 2 : 1) : 0}};
  const std::map<std::string, bool> flags = {{"bridgeGaps", true}, {"prune", s.prune},   {"cpc", s.cpc},
                                             {"refine", s.refine}, {"junctions", s.junctions},
                                             {"smooth", s.smooth}, {"repair", m.repair},
                                             {"keepDefective", m.allow_defects}, {"woodOnly", s.wood_only}};
  for (const auto& [script, count] : {std::pair<std::string, std::size_t>{"tree_skeleton.mlx", 20},
                                      std::pair<std::string, std::size_t>{"tree_mesh.mlx", 26}}) {
    std::ifstream in(std::string(TREESKEL_MESHLAB_SCRIPTS) + "/" + script);
    ASSERT_TRUE(in) << script;
    std::stringstream text;
    text << in.rdbuf();
    const std::string body = text.str();
    const std::regex param(R"re(<Param type="(\w+)" name="(\w+)" value="([^"]*)")re");
    std::size_t seen = 0;
    for (auto it = std::sregex_iterator(body.begin(), body.end(), param); it != std::sregex_iterator(); ++it, ++seen) {
      const std::string type = (*it)[1], name = (*it)[2], value = (*it)[3];
      if (type == "RichBool") {
        ASSERT_TRUE(flags.count(name)) << script << ": " << name;
        EXPECT_EQ(value, flags.at(name) ? "true" : "false") << script << ": " << name;
      } else {
        ASSERT_TRUE(expected.count(name)) << script << ": " << name;
        EXPECT_DOUBLE_EQ(std::stod(value), expected.at(name)) << script << ": " << name;
      }
    }
    EXPECT_EQ(seen, count) << script;
  }
}

}  // namespace
}  // namespace treeskel::meshlab
