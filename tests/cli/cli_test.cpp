// End-to-end runs of the treeskel command on real files.
#include "modeling/model_fixtures.h"
#include "run_tool.h"
#include "support/synthetic.h"
#include "treeskel/io/mesh_io.h"
#include "treeskel/io/point_cloud_io.h"
#include "treeskel/io/skeleton_io.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <random>

namespace treeskel {
namespace {

namespace fs = std::filesystem;

using test::quoted;
using test::Result;
using test::run;

TEST(Cli, NoInputRunsTheBundledExample) {
  const test::TempDir dir;
  const Result r = run("skeletonize", dir.root());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("tree_rtwig.txt: 14667 points"), std::string::npos) << r.out;
  ASSERT_TRUE(fs::exists(dir.path("tree_rtwig_skeleton.ply")));
  const Skeleton s = io::read_skeleton(dir.path("tree_rtwig_skeleton.ply"));
  EXPECT_TRUE(is_tree(s.graph));
  EXPECT_GT(count_branch_points(s.graph), 5u);
}

TEST(Cli, JsonReportAndEveryOutputFormat) {
  const test::TempDir dir;
  const std::string input = test::data_file("tree_adtree1.xyz");
  for (const char* ext : {"ply", "obj", "json"}) {
    const std::string out = dir.path(std::string("tree.") + ext);
    const Result r = run("skeletonize " + quoted(input) + " -o " + quoted(out) + " --json");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["points"], 11855);
    EXPECT_EQ(j["output"], out);
    EXPECT_EQ(j["nodes"].get<int>(), j["edges"].get<int>() + 1);
    EXPECT_GT(j["branch_points"].get<int>(), 3);
    EXPECT_TRUE(j.contains("left_out"));
    EXPECT_TRUE(j["stage_seconds"].contains("CPC"));
    EXPECT_TRUE(fs::file_size(out) > 100);
  }
}

// Twig pieces cut off by scan gaps: a lower floor for far bridging joins more of them to the tree
// (fewer points left out as small clusters, more nodes); 0 is refused.
TEST(Cli, FarBridgePointsSetsTheSmallestPartJoinedAcrossALongGap) {
  const test::TempDir dir;
  const std::string input = test::data_file("tree_adtree1.xyz");
  const auto skeleton = [&](const std::string& options) {
    const Result r = run("skeletonize " + quoted(input) + " -o " + quoted(dir.path("s.json")) + " --json " + options);
    EXPECT_EQ(r.code, 0) << r.out;
    return nlohmann::json::parse(r.out);
  };
  const auto plain = skeleton(""), ten = skeleton("--far-bridge-points 10"), three = skeleton("--far-bridge-points 3"),
             two = skeleton("--far-bridge-points 2");
  EXPECT_EQ(plain["nodes"], two["nodes"]);  // 2 is the default
  const auto left = [](const nlohmann::json& j) { return j["left_out"]["small_clusters"].get<int>(); };
  EXPECT_GT(left(ten), 0);
  EXPECT_LT(left(three), left(ten));
  EXPECT_LT(left(two), left(three));
  EXPECT_GT(three["nodes"].get<int>(), ten["nodes"].get<int>());
  EXPECT_GT(two["nodes"].get<int>(), three["nodes"].get<int>());
  const Result refused = run("skeletonize " + quoted(input) + " -o " + quoted(dir.path("bad.json")) + " --far-bridge-points 0");
  EXPECT_EQ(refused.code, 2) << refused.out;
  EXPECT_NE(refused.out.find("--far-bridge-points"), std::string::npos) << refused.out;
  EXPECT_FALSE(fs::exists(dir.path("bad.json")));
}

TEST(Cli, ReadsLasAndPlyAndKeepsTheInputFrame) {
  const test::TempDir dir;
  PointCloud c = io::read_point_cloud(test::data_file("tree_rtwig.txt"));
  c.offset += Eigen::Vector3d(300000.0, 5000000.0, 0.0);  // as if georeferenced
  io::write_point_cloud(dir.path("utm.las"), c);
  io::write_point_cloud(dir.path("utm.ply"), c);
  for (const char* name : {"utm.las", "utm.ply"}) {
    const Result r = run("skeletonize " + quoted(dir.path(name)) + " -o " + quoted(dir.path(std::string(name) + ".json")) + " -q");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(r.out, "");  // --quiet
    const Skeleton s = io::read_skeleton(dir.path(std::string(name) + ".json"));
    const Eigen::Vector3d root = s[s.root].position + s.offset;
    EXPECT_NEAR(root.x(), 300000.0 + 0.75, 1.0);
    EXPECT_NEAR(root.y(), 5000000.0 - 16.3, 1.0);
  }
}

TEST(Cli, BadInputFailsWithAMessageAndWritesNothing) {
  const test::TempDir dir;
  std::ofstream(dir.path("words.xyz")) << "1 2 3\n4 x 6\n";
  std::ofstream(dir.path("three.xyz")) << "0 0 0\n1 0 0\n0 1 0\n";
  std::ofstream(dir.path("line.xyz")) << "0 0 0\n1 1 1\n2 2 2\n3 3 3\n4 4 4\n5 5 5\n6 6 6\n7 7 7\n8 8 8\n9 9 9\n10 10 10\n";
  std::ofstream(dir.path("empty.xyz"));
  const std::pair<std::string, std::string> cases[] = {
      {"missing.xyz", "no such file"},   {"words.xyz", "line 2"},     {"three.xyz", "at least 10"},
      {"line.xyz", "one straight line"}, {"empty.xyz", "is empty"},
  };
  for (const auto& [name, message] : cases) {
    const std::string out = dir.path(name + ".ply");
    const Result r = run("skeletonize " + quoted(dir.path(name)) + " -o " + quoted(out));
    EXPECT_EQ(r.code, 1) << name << ": " << r.out;
    EXPECT_NE(r.out.find(message), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(name), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(out));
  }
  // An existing output is not overwritten by a failed run.
  const std::string keep = dir.path("keep.ply");
  std::ofstream(keep) << "old";
  EXPECT_EQ(run("skeletonize " + quoted(dir.path("words.xyz")) + " -o " + quoted(keep)).code, 1);
  std::ifstream in(keep);
  std::string old;
  in >> old;
  EXPECT_EQ(old, "old");
  // Unknown output extension: refused before any work.
  const Result bad = run("skeletonize -o " + quoted(dir.path("tree.stl")));
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.out.find("unknown skeleton extension"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir.path("tree.stl")));
  // Only the files the test made are in the folder: no temporaries left behind.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.root()), fs::directory_iterator()), 5);
}

/// How many files of `folder` have names ending in `suffix`.
std::size_t files_ending(const std::string& folder, const std::string& suffix) {
  std::size_t n = 0;
  for (const auto& entry : fs::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    n += name.size() >= suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
  }
  return n;
}

TEST(Cli, SynthWritesTheBenchmarkAndEvalScoresIt) {
  const test::TempDir dir;
  const Result synth = run("synth " + quoted(dir.path("bench")) + " --seed 3 -q");
  ASSERT_EQ(synth.code, 0) << synth.out;
  EXPECT_EQ(files_ending(dir.path("bench"), ".xyz"), 72u);
  EXPECT_EQ(files_ending(dir.path("bench"), "_truth.json") + files_ending(dir.path("bench"), "_truth.ply"), 12u);
  // The ground truth scored against itself is perfect; a skeleton of one of its clouds is close.
  const std::string truth = quoted(dir.path("bench/tree2_truth.json"));
  const Result self = run("eval " + truth + " " + quoted(dir.path("bench/tree2_truth.ply")) + " --json");
  ASSERT_EQ(self.code, 0) << self.out;
  const auto j = nlohmann::json::parse(self.out);
  EXPECT_EQ(j["spd"], 0.0);
  EXPECT_EQ(j["bpc"], 1.0);
  EXPECT_EQ(j["branch_points"]["truth"], 11);
  const std::string predicted = quoted(dir.path("tree2.ply"));
  ASSERT_EQ(run("skeletonize " + quoted(dir.path("bench/tree2_16647.xyz")) + " -o " + predicted + " -q").code, 0);
  const Result scored = run("eval " + predicted + " " + truth);
  ASSERT_EQ(scored.code, 0) << scored.out;
  EXPECT_NE(scored.out.find("BPC"), std::string::npos);
  EXPECT_EQ(run("eval " + quoted(dir.path("none.ply")) + " " + truth).code, 1);
}

TEST(Cli, SynthWritesTheHarderSetsEachCloudWithItsTruth) {
  const test::TempDir dir;
  const Result synth = run("synth " + quoted(dir.path("hard")) + " --set hard --format ply -q");
  ASSERT_EQ(synth.code, 0) << synth.out;
  EXPECT_EQ(files_ending(dir.path("hard"), ".ply"), 33u);
  EXPECT_EQ(files_ending(dir.path("hard"), "_truth.json"), 33u);
  // A sparse scan's truth is cut back to what the scan shows: fewer forks than the grown tree's 230.
  const Result self = run("eval " + quoted(dir.path("hard/sparse230_1view_2529_truth.json")) + " " +
                          quoted(dir.path("hard/sparse230_1view_2529_truth.json")) + " --json");
  ASSERT_EQ(self.code, 0) << self.out;
  const auto j = nlohmann::json::parse(self.out);
  EXPECT_EQ(j["bpc"], 1.0);
  EXPECT_LT(j["branch_points"]["truth"].get<int>(), 230);
  EXPECT_EQ(run("synth " + quoted(dir.path("other")) + " --set crowded").code, 2);
}

TEST(Cli, UsageErrorsAndHelp) {
  EXPECT_EQ(run("").code, 2);
  EXPECT_EQ(run("skeletonize --depth 40").code, 2);
  EXPECT_EQ(run("skeletonize --neighbours magic").code, 2);
  const Result help = run("skeletonize --help");
  EXPECT_EQ(help.code, 0);
  for (const char* option : {"--band", "--cpc-weight", "--eta", "--bridge", "--up", "--json", "--no-refine"})
    EXPECT_NE(help.out.find(option), std::string::npos) << option;
  EXPECT_NE(help.out.find("100"), std::string::npos);  // defaults are shown
}

TEST(Cli, ModelTurnsTheExampleIntoAGlbWithReportAndQsm) {
  test::TempDir dir;
  const Result r = run("model -o tree.glb --report report.json --qsm qsm.csv --skeleton skeleton.json", dir.root());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("closed, manifold, no self-intersection"), std::string::npos) << r.out;
  EXPECT_GT(fs::file_size(dir.path("tree.glb")), 1000u);
  std::ifstream in(dir.path("report.json"));
  const auto j = nlohmann::json::parse(in);
  EXPECT_TRUE(j["mesh"]["closed"].get<bool>());
  EXPECT_EQ(j["mesh"]["self_intersections"].get<int>(), 0);
  EXPECT_EQ(j["mesh"]["components"].get<int>(), 1);
  EXPECT_GT(j["mesh"]["volume"].get<double>(), 0.0);
  EXPECT_GE(j["mesh"]["skeleton_coverage"].get<double>(), 0.95);
  EXPECT_NE(r.out.find("% of the skeleton inside"), std::string::npos) << r.out;
  EXPECT_TRUE(j["frame"]["y_up_rotation"].get<bool>());  // glTF is Y up; the cloud is Z up
  ASSERT_TRUE(j["measurements"].contains("dbh"));
  EXPECT_GT(j["measurements"]["dbh"].get<double>(), 0.0);  // the rTwig tree is 3.7 m tall
  EXPECT_EQ(j["measurements"]["dbh_source"], "points");   // a circle fitted at breast height
  EXPECT_GT(j["measurements"]["height"].get<double>(), 3.0);
  // Where the time went: the stages, none negative, add up to the total.
  double stages = 0.0;
  for (const char* stage : {"skeleton", "radii", "mesh", "checks", "measure_and_write"}) {
    ASSERT_TRUE(j["seconds"].contains(stage)) << stage;
    EXPECT_GE(j["seconds"][stage].get<double>(), 0.0) << stage;
    stages += j["seconds"][stage].get<double>();
  }
  EXPECT_NEAR(stages, j["seconds"]["total"].get<double>(), 1e-9);
  EXPECT_GT(j["seconds"]["mesh"].get<double>(), 0.0);
  // The mesh's stages: none negative, the tests part of the sweep, together within the mesh's time.
  double mesh_stages = 0.0;
  for (const char* stage : {"sweep", "whole_mesh_tests", "pieces", "unions"}) {
    ASSERT_TRUE(j["mesh_seconds"].contains(stage)) << stage;
    EXPECT_GE(j["mesh_seconds"][stage].get<double>(), 0.0) << stage;
    if (std::string(stage) != "whole_mesh_tests") mesh_stages += j["mesh_seconds"][stage].get<double>();
  }
  EXPECT_GT(j["mesh_seconds"]["sweep"].get<double>(), 0.0);
  EXPECT_GT(j["mesh_seconds"]["whole_mesh_tests"].get<double>(), 0.0);
  EXPECT_LE(j["mesh_seconds"]["whole_mesh_tests"].get<double>(), j["mesh_seconds"]["sweep"].get<double>());
  EXPECT_LE(mesh_stages, j["seconds"]["mesh"].get<double>());
  std::ifstream csv(dir.path("qsm.csv"));
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("id,parent,branch,order,", 0), 0u);
  // The saved skeleton (radii fitted) goes back in and gives a mesh again.
  const Result again = run("model skeleton.json -o again.obj --json", dir.root());
  ASSERT_EQ(again.code, 0) << again.out;
  EXPECT_TRUE(nlohmann::json::parse(again.out)["radii"]["from_stored_radii"].get<bool>());
  EXPECT_TRUE(fs::exists(dir.path("again.obj")));
  // Outside --json the user is told the radii are the file's, not fitted to points.
  const Result told = run("model skeleton.json -o again.stl", dir.root());
  ASSERT_EQ(told.code, 0) << told.out;
  EXPECT_NE(told.out.find("note: the radii are the skeleton file's"), std::string::npos) << told.out;
}

// AdTree's tree1 (bundled): forks whose joins leave no room for a limb. The mesh holds the whole
// skeleton, and the file, read back as a viewer reads it, is the mesh that was checked.
TEST(Cli, ModelOfACrowdedCrownHoldsTheWholeSkeletonInTheFile) {
  test::TempDir dir;
  const std::string cloud = test::data_file("tree_adtree1.xyz");
  const Result r = run("model " + cloud + " -o tree.ply --report report.json", dir.root());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(r.out.find("warning"), std::string::npos) << r.out;
  std::ifstream in(dir.path("report.json"));
  const auto j = nlohmann::json::parse(in);
  EXPECT_GE(j["mesh"]["skeleton_coverage"].get<double>(), 0.97);
  EXPECT_GT(j["mesh"]["pieces_united"].get<int>(), 0);
  EXPECT_EQ(j["mesh"]["pieces_failed"].get<int>(), 0);
  EXPECT_EQ(j["mesh"]["components"].get<int>(), 1);
  const modeling::TreeMesh back = io::read_mesh(dir.path("tree.ply"));
  EXPECT_EQ(back.n_faces(), j["mesh"]["triangles"].get<std::size_t>());
  const modeling::MeshCheck check = modeling::check_mesh(back, true);
  EXPECT_TRUE(check.ok()) << check.problem();
}

// --complete grows branches through the points the model passed by (AdTree's tree1 has a crowded
// crown), says so in the summary and the report, and the mesh still passes every check; a saved
// skeleton has no points to grow through, which a note says.
TEST(Cli, ModelCompleteGrowsBranchesThroughThePointsItPassedBy) {
  test::TempDir dir;
  const std::string cloud = test::data_file("tree_adtree1.xyz");
  const Result plain = run("model " + cloud + " -o plain.ply --json --skeleton s.json", dir.root());
  ASSERT_EQ(plain.code, 0) << plain.out;
  const auto before = nlohmann::json::parse(plain.out);
  EXPECT_FALSE(before["completion"]["run"].get<bool>());
  EXPECT_EQ(before["completion"]["nodes"].get<int>(), 0);
  const Result r = run("model " + cloud + " --complete -o tree.ply --report report.json", dir.root());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("branches grown through"), std::string::npos) << r.out;
  std::ifstream in(dir.path("report.json"));
  const auto j = nlohmann::json::parse(in);
  EXPECT_TRUE(j["completion"]["run"].get<bool>());
  EXPECT_GE(j["completion"]["branches"].get<int>(), 3);
  EXPECT_GT(j["completion"]["grafted_points"].get<int>(), 100);
  EXPECT_LE(j["completion"]["grafted_points"].get<int>() + j["completion"]["bushy_points"].get<int>(),
            j["completion"]["uncovered_points"].get<int>());
  EXPECT_EQ(j["nodes"].get<int>(), before["nodes"].get<int>() + j["completion"]["nodes"].get<int>());
  EXPECT_TRUE(j["mesh"]["closed"].get<bool>());
  EXPECT_EQ(j["mesh"]["self_intersections"].get<int>(), 0);
  EXPECT_GE(j["mesh"]["skeleton_coverage"].get<double>(), 0.95);
  const modeling::MeshCheck check = modeling::check_mesh(io::read_mesh(dir.path("tree.ply")), true);
  EXPECT_TRUE(check.ok()) << check.problem();
  const Result saved = run("model s.json --complete -o again.ply", dir.root());
  ASSERT_EQ(saved.code, 0) << saved.out;
  EXPECT_NE(saved.out.find("--complete needs the cloud's points"), std::string::npos) << saved.out;
}

// --complete-all grows the tufts and bushes --complete leaves out: more of tree1's points grafted, no
// bush left, the report says which was asked, and the mesh still passes every check.
TEST(Cli, ModelCompleteAllGrowsTheTuftsAndBushesToo) {
  test::TempDir dir;
  const std::string cloud = test::data_file("tree_adtree1.xyz");
  const Result some = run("model " + cloud + " --complete -o some.ply --json", dir.root());
  ASSERT_EQ(some.code, 0) << some.out;
  const auto before = nlohmann::json::parse(some.out);
  EXPECT_FALSE(before["completion"]["tufts_and_bushes"].get<bool>());
  const Result r = run("model " + cloud + " --complete-all -o all.ply --json", dir.root());
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["completion"]["run"].get<bool>());
  EXPECT_TRUE(j["completion"]["tufts_and_bushes"].get<bool>());
  EXPECT_EQ(j["completion"]["bushy_grafts"].get<int>(), 0);
  EXPECT_GT(j["completion"]["grafted_points"].get<int>(), 2 * before["completion"]["grafted_points"].get<int>());
  EXPECT_EQ(j["completion"]["uncovered_points"].get<int>(), before["completion"]["uncovered_points"].get<int>());
  EXPECT_TRUE(j["mesh"]["closed"].get<bool>());
  EXPECT_EQ(j["mesh"]["self_intersections"].get<int>(), 0);
  EXPECT_EQ(j["mesh"]["components"].get<int>(), 1);
  EXPECT_GE(j["mesh"]["skeleton_coverage"].get<double>(), 0.95);
  const modeling::MeshCheck check = modeling::check_mesh(io::read_mesh(dir.path("all.ply")), true);
  EXPECT_TRUE(check.ok()) << check.problem();
}

// The limbs are straightened by default (stiffness 2, in the report, with what moved); --stiffness 0
// keeps the skeleton's path, node for node what `skeletonize` pruned as a model writes but the root,
// which goes down its trunk to where its points end (in the report too); a negative stiffness is
// refused. The stubs found are in the report too (35 on this tree; none with --stub-length 0).
TEST(Cli, ModelStraightensTheLimbsUnlessTheStiffnessIsZero) {
  test::TempDir dir;
  const std::string cloud = test::data_file("tree_adtree1.xyz");
  const Result straight = run("model " + cloud + " -o a.ply --skeleton a.json --json", dir.root());
  ASSERT_EQ(straight.code, 0) << straight.out;
  const auto j = nlohmann::json::parse(straight.out)["radii"];
  EXPECT_EQ(j["stiffness"].get<double>(), 2.0);
  EXPECT_GT(j["straightened_nodes"].get<int>(), 0);
  EXPECT_EQ(j["stub_length"].get<double>(), 6.5);  // and the stubs found (FitRadii.TipsShorterThan...)
  EXPECT_GT(j["stubs"].get<int>(), 0);
  EXPECT_GT(j["largest_shift"].get<double>(), 0.0);
  const Result kept = run("model " + cloud + " -o b.ply --skeleton b.json --stiffness 0 --json", dir.root());
  ASSERT_EQ(kept.code, 0) << kept.out;
  EXPECT_EQ(nlohmann::json::parse(kept.out)["radii"]["straightened_nodes"].get<int>(), 0);
  const Result twigs = run("model " + cloud + " -o d.ply --stub-length 0 --json", dir.root());
  ASSERT_EQ(twigs.code, 0) << twigs.out;
  EXPECT_EQ(nlohmann::json::parse(twigs.out)["radii"]["stubs"].get<int>(), 0);
  EXPECT_NE(run("model " + cloud + " -o e.ply --stub-length -1", dir.root()).code, 0);
  // A model prunes less than skeletonize (modeling::use_model_pruning: spurs within 1 of the nodes'
  // radii, not 2.25 of the points' spread, leaves under a whole band, none at close forks): pruned as
  // a model prunes, skeletonize gives the same nodes; pruned as it does by default, fewer.
  const Result plain = run("skeletonize " + cloud +
                               " -o c.json --prune-radius 1 --prune-point-radius 0 --prune-bands 1 --close-forks 0",
                           dir.root());
  ASSERT_EQ(plain.code, 0) << plain.out;
  const Result pruned = run("skeletonize " + cloud + " -o p.json", dir.root());
  ASSERT_EQ(pruned.code, 0) << pruned.out;
  const Skeleton a = io::read_skeleton(dir.path("a.json")), b = io::read_skeleton(dir.path("b.json")),
                 c = io::read_skeleton(dir.path("c.json"));
  EXPECT_LT(io::read_skeleton(dir.path("p.json")).node_count(), c.node_count());
  ASSERT_EQ(a.node_count(), c.node_count());
  ASSERT_EQ(b.node_count(), c.node_count());
  std::size_t moved = 0;
  const double lowered = nlohmann::json::parse(kept.out)["radii"]["base_lowered"].get<double>();
  EXPECT_GT(lowered, 0.0);
  EXPECT_NEAR((b[b.root].position - c[c.root].position).norm(), lowered, 1e-3);
  EXPECT_LT(b[b.root].position.z(), c[c.root].position.z());
  for (NodeId v = 0; v < c.node_count(); ++v) {
    if (v == c.root) continue;
    EXPECT_LT((b[v].position - c[v].position).norm(), 1e-3) << v;  // the JSON's digits
    if ((a[v].position - c[v].position).norm() > 1e-3) ++moved;
  }
  EXPECT_GT(moved, 100u);
  const Result refused = run("model " + cloud + " --stiffness -1 -o bad.ply", dir.root());
  EXPECT_EQ(refused.code, 2) << refused.out;
  EXPECT_NE(refused.out.find("--stiffness"), std::string::npos) << refused.out;
}

// The stem's shares are bounded by default (4, in the report); --stem-share-bound 0 turns the bound
// off and changes the radii; a bound under 1 is refused by name.
TEST(Cli, ModelBoundsTheStemsSharesUnlessTurnedOff) {
  test::TempDir dir;
  const std::string cloud = test::data_file("tree_adtree1.xyz");
  const Result r = run("model " + cloud + " --stem-share-bound 0 -o tree.ply --report report.json", dir.root());
  ASSERT_EQ(r.code, 0) << r.out;
  std::ifstream in(dir.path("report.json"));
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["radii"]["stem_share_bound"].get<double>(), 0.0);
  EXPECT_TRUE(j["mesh"]["closed"].get<bool>());
  EXPECT_EQ(j["mesh"]["self_intersections"].get<int>(), 0);
  const modeling::MeshCheck check = modeling::check_mesh(io::read_mesh(dir.path("tree.ply")), true);
  EXPECT_TRUE(check.ok()) << check.problem();
  const Result plain = run("model " + cloud + " -o plain.ply --json", dir.root());
  ASSERT_EQ(plain.code, 0) << plain.out;
  const auto bounded = nlohmann::json::parse(plain.out);
  EXPECT_EQ(bounded["radii"]["stem_share_bound"].get<double>(), 4.0);
  EXPECT_NE(bounded["mesh"]["volume"].get<double>(), j["mesh"]["volume"].get<double>());
  for (const std::string bad : {"0.5", "inf", "4x"}) {
    const Result refused = run("model " + cloud + " --stem-share-bound " + bad + " -o bad.ply", dir.root());
    EXPECT_EQ(refused.code, 2) << bad << ": " << refused.out;
    EXPECT_NE(refused.out.find("--stem-share-bound"), std::string::npos) << refused.out;
    EXPECT_FALSE(std::filesystem::exists(dir.path("bad.ply")));
  }
}

// A Y-up cloud modeled as Z-up, and the same cloud in millimetres, are warned about.
TEST(Cli, ModelWarnsAboutAnUpAxisOrUnitsThatLookWrong) {
  test::TempDir dir;
  const PointCloud tree = io::read_point_cloud(test::data_file("tree_rtwig.txt"));
  {
    std::ofstream y_up(dir.path("y_up.xyz")), mm(dir.path("mm.xyz"));
    for (const auto& p : tree.positions) {
      const Eigen::Vector3d w = p + tree.offset;
      y_up << w.x() << ' ' << w.z() << ' ' << w.y() << '\n';
      mm << 1000 * w.x() << ' ' << 1000 * w.y() << ' ' << 1000 * w.z() << '\n';
    }
  }
  const Result lying = run("model y_up.xyz -o y.glb --report y.json", dir.root());
  ASSERT_EQ(lying.code, 0) << lying.out;
  EXPECT_NE(lying.out.find("wider than tall along the up axis"), std::string::npos) << lying.out;
  const Result upright = run("model y_up.xyz --up y -o y2.glb", dir.root());
  ASSERT_EQ(upright.code, 0) << upright.out;
  EXPECT_EQ(upright.out.find("wider than tall"), std::string::npos) << upright.out;
  const Result millimetres = run("model mm.xyz -o mm.glb --report mm.json", dir.root());
  ASSERT_EQ(millimetres.code, 0) << millimetres.out;
  EXPECT_NE(millimetres.out.find("centimetres or millimetres"), std::string::npos) << millimetres.out;
  std::ifstream in(dir.path("mm.json"));
  EXPECT_FALSE(nlohmann::json::parse(in)["warnings"].empty());
}

// A tree scanned standing on its ground: the skeleton roots in a disc of ground and the octree's
// cells grow with it. --set-ground-aside sets the ground aside and says how much.
TEST(Cli, ModelSetsAsideTheGroundATreeStandsOnWhenAsked) {
  test::TempDir dir;
  const PointCloud tree = io::read_point_cloud(test::data_file("tree_adtree1.xyz"));
  std::size_t disc = 0;
  {
    double low = 1e300;
    Eigen::Vector3d foot = Eigen::Vector3d::Zero();
    for (const auto& p : tree.positions) low = std::min(low, p.z());
    std::size_t n = 0;
    for (const auto& p : tree.positions)
      if (p.z() < low + 0.3) foot += p, ++n;
    foot /= static_cast<double>(n);
    std::ofstream out(dir.path("on_ground.xyz"));
    out.precision(10);
    std::mt19937_64 rng(1);
    std::normal_distribution<double> noise(0.0, 0.01);
    for (int i = -75; i <= 75; ++i)
      for (int j = -75; j <= 75; ++j) {
        const double x = 0.04 * i, y = 0.04 * j;
        if (std::hypot(x, y) <= 0.12 || std::hypot(x, y) >= 3.0) continue;
        const Eigen::Vector3d w = Eigen::Vector3d(foot.x() + x, foot.y() + y, low + noise(rng)) + tree.offset;
        out << w.x() << ' ' << w.y() << ' ' << w.z() << '\n';
        ++disc;
      }
    for (const auto& p : tree.positions) {
      const Eigen::Vector3d w = p + tree.offset;
      out << w.x() << ' ' << w.y() << ' ' << w.z() << '\n';
    }
  }
  const auto report = [&](const std::string& name) {
    std::ifstream in(dir.path(name));
    return nlohmann::json::parse(in);
  };
  ASSERT_EQ(run("model on_ground.xyz -o kept.glb --report kept.json -q", dir.root()).code, 0);
  const Result aside = run("model on_ground.xyz -o aside.glb --report aside.json --set-ground-aside", dir.root());
  ASSERT_EQ(aside.code, 0) << aside.out;
  EXPECT_NE(aside.out.find("points of ground and what lies on it around the stem's foot (--set-ground-aside)"),
            std::string::npos) << aside.out;
  ASSERT_EQ(run("model " + quoted(test::data_file("tree_adtree1.xyz")) + " -o alone.glb --report alone.json -q", dir.root()).code, 0);
  const auto kept = report("kept.json"), set = report("aside.json"), alone = report("alone.json");
  EXPECT_EQ(kept["ground_set_aside"], 0);
  // The disc, and no more than a few dozen of the stem's lowest points with it.
  EXPECT_GE(set["ground_set_aside"].get<std::size_t>(), disc - disc / 100);
  EXPECT_LE(set["ground_set_aside"].get<std::size_t>(), disc + 100);
  // The tree's skeleton at its own resolution again, and its height as without the ground (its
  // DBH is not compared: on this tree one point a few centimetres under the base moves it by a
  // quarter, ground or not; see docs/models.md).
  EXPECT_NEAR(set["nodes"].get<double>(), alone["nodes"].get<double>(), 0.05 * alone["nodes"].get<double>());
  // Kept, the ground is in the skeleton: a disc of nodes around the stem's foot (1.16 times the
  // tree's nodes; with a density target of 2 points a cell, the ground coarsened the cells instead:
  // 0.66 of them).
  EXPECT_GT(kept["nodes"].get<double>(), 1.1 * alone["nodes"].get<double>());
  EXPECT_NEAR(set["measurements"]["height"].get<double>(), alone["measurements"]["height"].get<double>(), 0.05);
}

// Two trees side by side, 20 m apart: one is modelled, and the other is not left out silently.
TEST(Cli, ModelWarnsWhenACloudHoldsSeveralTrees) {
  test::TempDir dir;
  const PointCloud tree = io::read_point_cloud(test::data_file("tree_rtwig.txt"));
  {
    std::ofstream two(dir.path("two.xyz"));
    for (const double shift : {0.0, 20.0})
      for (const auto& p : tree.positions) {
        const Eigen::Vector3d w = p + tree.offset;
        two << w.x() + shift << ' ' << w.y() << ' ' << w.z() << '\n';
      }
  }
  const Result two = run("model two.xyz -o two.glb --report two.json", dir.root());
  ASSERT_EQ(two.code, 0) << two.out;
  EXPECT_NE(two.out.find("several trees"), std::string::npos) << two.out;
  EXPECT_NE(two.out.find("'treeskel plot' models each tree"), std::string::npos) << two.out;
  std::ifstream in(dir.path("two.json"));
  const auto warnings = nlohmann::json::parse(in)["warnings"];
  EXPECT_TRUE(std::any_of(warnings.begin(), warnings.end(),
                          [](const nlohmann::json& w) { return w.get<std::string>().find("several trees") != std::string::npos; }));
  const Result one = run("model " + quoted(test::data_file("tree_rtwig.txt")) + " -o one.glb", dir.root());
  ASSERT_EQ(one.code, 0) << one.out;
  EXPECT_EQ(one.out.find("several trees"), std::string::npos) << one.out;
}

TEST(Cli, ModelFormatsAndBadUse) {
  test::TempDir dir;
  const std::string cloud = quoted(test::data_file("tree_adtree1.xyz"));
  for (const char* ext : {"obj", "ply", "stl", "gltf"}) {
    const Result r = run("model " + cloud + " -q -o tree." + ext, dir.root());
    EXPECT_EQ(r.code, 0) << ext << r.out;
    EXPECT_TRUE(fs::exists(dir.path(std::string("tree.") + ext))) << ext;
  }
  const Result bad_ext = run("model " + cloud + " -o tree.fbx", dir.root());
  EXPECT_EQ(bad_ext.code, 2);  // a usage error
  EXPECT_NE(bad_ext.out.find("unknown mesh extension"), std::string::npos) << bad_ext.out;
  EXPECT_FALSE(fs::exists(dir.path("tree.fbx")));
  // A skeleton saved by `skeletonize` has zero radii where none was measured: the pipe model fills
  // them in from the positive ones.
  {
    std::ofstream out(dir.path("zero.json"));
    out << R"({"format":"treeskel skeleton","version":1,"root":0,"nodes":[)"
        << R"({"id":0,"position":[0,0,0],"radius":0.1},{"id":1,"position":[0,0,1],"radius":0}],"edges":[[0,1]]})";
  }
  const Result zero = run("model zero.json -o zero.glb", dir.root());
  EXPECT_EQ(zero.code, 0) << zero.out;
  EXPECT_NE(zero.out.find("the pipe model fills them in"), std::string::npos) << zero.out;
  EXPECT_TRUE(fs::exists(dir.path("zero.glb")));
  // A skeleton at georeferenced coordinates is swept in its local frame: twigs a few millimetres
  // long at UTM coordinates (where a millimetre is a billionth of the coordinates) are meshed, and
  // the OBJ is in the input's frame.
  {
    std::ofstream out(dir.path("utm.json"));
    out << R"({"format":"treeskel skeleton","version":1,"root":0,"nodes":[)"
        << R"({"id":0,"position":[600000.5,5200000.5,100],"radius":0.05},)"
        << R"({"id":1,"position":[600000.5,5200000.5,101],"radius":0.03},)"
        << R"({"id":2,"position":[600000.5,5200000.5,102],"radius":0.0015},)"
        << R"({"id":3,"position":[600000.502,5200000.5,102.003],"radius":0.001},)"
        << R"({"id":4,"position":[600000.498,5200000.5,102.003],"radius":0.001}],)"
        << R"("edges":[[0,1],[1,2],[2,3],[2,4]]})";
  }
  const Result utm = run("model utm.json -o utm.obj", dir.root());
  ASSERT_EQ(utm.code, 0) << utm.out;
  {
    std::ifstream in(dir.path("utm.obj"));
    std::string tag;
    double x = 0, y = 0, z = 0;
    std::size_t vertices = 0;
    for (std::string line; std::getline(in, line);) {
      std::istringstream fields(line);
      if (!(fields >> tag >> x >> y >> z) || tag != "v") continue;
      ++vertices;
      EXPECT_NEAR(x, 600000.5, 0.1);
      EXPECT_NEAR(y, 5200000.5, 0.1);
      EXPECT_GT(z, 99.9);
      EXPECT_LT(z, 102.1);
    }
    EXPECT_GT(vertices, 20u);
  }
  // Three branches along one line from a fork: the sweep makes them one tube of a little more than
  // half their radius, so the mesh holds about 60% of the wood the radii describe, and the summary
  // and the report warn; a single straight branch does not.
  {
    std::ofstream out(dir.path("overlap.json"));
    out << R"({"format":"treeskel skeleton","version":1,"root":0,"nodes":[)"
        << R"({"id":0,"position":[0,0,0],"radius":0.1},{"id":1,"position":[0,0,1],"radius":0.1},)"
        << R"({"id":2,"position":[0,0,4],"radius":0.0577},{"id":3,"position":[0.001,0,4],"radius":0.0577},)"
        << R"({"id":4,"position":[0,0.001,4],"radius":0.0577}],"edges":[[0,1],[1,2],[1,3],[1,4]]})";
  }
  const Result overlap = run("model overlap.json -o overlap.glb --report overlap_report.json", dir.root());
  ASSERT_EQ(overlap.code, 0) << overlap.out;
  EXPECT_NE(overlap.out.find("of the wood the fitted radii describe"), std::string::npos) << overlap.out;
  {
    std::ifstream in(dir.path("overlap_report.json"));
    const auto report = nlohmann::json::parse(in);
    EXPECT_LT(report.at("mesh").at("wood_inside").get<double>(), 0.85);
    bool listed = false;
    for (const auto& w : report.at("warnings"))
      listed = listed || w.get<std::string>().find("of the wood the fitted radii describe") != std::string::npos;
    EXPECT_TRUE(listed);
  }
  EXPECT_EQ(zero.out.find("of the wood the fitted radii describe"), std::string::npos) << zero.out;
  EXPECT_NE(zero.out.find("% of its wood)"), std::string::npos) << zero.out;
  // A negative radius, an empty skeleton and one with a cycle are refused; nothing is written.
  {
    std::ofstream out(dir.path("negative.json"));
    out << R"({"format":"treeskel skeleton","version":1,"root":0,"nodes":[)"
        << R"({"id":0,"position":[0,0,0],"radius":0.1},{"id":1,"position":[0,0,1],"radius":-1}],"edges":[[0,1]]})";
  }
  {
    std::ofstream out(dir.path("cycle.json"));
    out << R"({"format":"treeskel skeleton","version":1,"root":0,"nodes":[)"
        << R"({"id":0,"position":[0,0,0],"radius":0.1},{"id":1,"position":[0,0,1],"radius":0.1},)"
        << R"({"id":2,"position":[1,0,1],"radius":0.1}],"edges":[[0,1],[1,2],[2,0]]})";
  }
  {
    std::ofstream out(dir.path("empty.json"));
    out << R"({"format":"treeskel skeleton","version":1,"root":0,"nodes":[],"edges":[]})";
  }
  for (const char* name : {"negative", "cycle", "empty"}) {
    const Result r = run(std::string("model ") + name + ".json -o " + name + ".glb", dir.root());
    EXPECT_EQ(r.code, 1) << name << r.out;
    EXPECT_NE(r.out.find("error"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(dir.path(std::string(name) + ".glb"))) << name;
  }
  const Result help = run("model --help");
  EXPECT_EQ(help.code, 0);
  EXPECT_NE(help.out.find("--exponent"), std::string::npos);
  EXPECT_NE(help.out.find("--qsm"), std::string::npos);
}

std::string text_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// Names in `dir` that treeskel's temporary files and folders start with.
int temporaries_in(const std::string& dir) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(dir)) n += e.path().filename().string().rfind(".treeskel-", 0) == 0;
  return n;
}

// A disk that refuses the data (here a file size limit, as a full disk or a quota does) fails the run
// and leaves the old file as it was, in every mesh format. The input is a small saved skeleton, so
// that the test is quick (the sanitizer build runs it too).
TEST(Cli, FullDiskFailsAndKeepsTheOldFile) {
  const test::TempDir dir;
  io::write_skeleton(dir.path("y.json"), test::y_shape(0.05, 0.6, 20));
  for (const char* ext : {"obj", "ply", "stl", "glb", "gltf"}) {
    const std::string out = dir.path(std::string("m.") + ext);
    std::ofstream(out) << "old";
    // ulimit -f counts 512-byte blocks in dash: 4 KB, less than any of these meshes.
    const Result r = run("model y.json -o " + quoted(out) + " -q", dir.root(), "ulimit -f 8;");
    EXPECT_EQ(r.code, 1) << ext << ": " << r.out;
    EXPECT_NE(r.out.find("writing failed"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find(".treeskel-"), std::string::npos) << "the message names a temporary file: " << r.out;
    EXPECT_EQ(text_of(out), "old") << ext;
    EXPECT_EQ(temporaries_in(dir.root()), 0) << ext;
    EXPECT_FALSE(fs::exists(dir.path("m.bin"))) << ext;
    // Without the limit the same run writes the file.
    EXPECT_EQ(run("model y.json -o " + quoted(out) + " -q", dir.root()).code, 0) << ext;
    std::uintmax_t written = 0;  // the file and, for .gltf, its .bin
    for (const auto& e : fs::directory_iterator(dir.root()))
      if (e.path().stem() == "m" || e.path().stem() == "m_0") written += e.file_size();
    EXPECT_GT(written, 4096u) << ext;
    for (const auto& e : fs::directory_iterator(dir.root()))
      if (e.path().filename() != "y.json") fs::remove(e.path());
  }
}

TEST(Cli, AnOutputThatIsTheInputIsRefused) {
  const test::TempDir dir;
  io::write_point_cloud(dir.path("c.ply"), io::read_point_cloud(test::data_file("tree_rtwig.txt")));
  const std::string before = text_of(dir.path("c.ply"));
  Result r = run("skeletonize c.ply -o c.ply", dir.root());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("is the input"), std::string::npos) << r.out;
  fs::create_symlink(dir.path("c.ply"), dir.path("link.ply"));
  r = run("skeletonize c.ply -o link.ply", dir.root());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_EQ(text_of(dir.path("c.ply")), before);
  EXPECT_EQ(temporaries_in(dir.root()), 0);
}

// Every output is checked before any work, and none is written when one cannot be.
TEST(Cli, SideOutputsAreCheckedBeforeAnyWork) {
  const test::TempDir dir;
  fs::create_directory(dir.path("folder.csv"));
  for (const std::string side : {"--report nodir/r.json", "--qsm nodir/q.csv", "--skeleton nodir/s.ply",
                                 "--qsm folder.csv", "--report m.glb"}) {
    const Result r = run("model -o m.glb " + side, dir.root());
    EXPECT_EQ(r.code, 2) << side << ": " << r.out;
    EXPECT_FALSE(fs::exists(dir.path("m.glb"))) << side;
    EXPECT_EQ(r.out.find("reading"), std::string::npos) << side << ": " << r.out;
  }
  EXPECT_EQ(temporaries_in(dir.root()), 0);
}

// --wood-only on a real tree in leaf: the leaves set aside, written, counted in the report; the model
// of the rest; the leaves refused without it; the batch runner writes each tree's leaves beside it.
TEST(Cli, WoodOnlySetsTheLeavesOfALeafyTreeAside) {
  const test::TempDir dir;
  const std::string cloud = quoted(test::data_file("tree_arbor_leafy.xyz"));
  const Result r = run("model " + cloud + " --wood-only --leaves leaves.ply -o m.ply --report r.json", dir.root());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("--wood-only: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("a cloud in leaf: the ways from its base through the points counted"), std::string::npos) << r.out;
  std::ifstream in(dir.path("r.json"));
  const auto report = nlohmann::json::parse(in);
  EXPECT_EQ(report.at("wood_only").at("in_leaf").get<double>(), 1.0);
  const std::size_t wood = report.at("wood_only").at("wood_points"), leaves = report.at("wood_only").at("leaf_points");
  EXPECT_EQ(wood + leaves, 36478u);
  EXPECT_EQ(report.at("points").get<std::size_t>(), wood);
  EXPECT_GT(leaves, 36478u / 6) << "a fifth to a third of this tree is leaves";
  EXPECT_LT(leaves, 36478u / 3);
  const PointCloud set_aside = io::read_point_cloud(dir.path("leaves.ply"));
  EXPECT_EQ(set_aside.size(), leaves);
  // In the input's frame, as every output: UTM metres.
  EXPECT_GT(set_aside.positions.front().x() + set_aside.offset.x(), 269000.0);
  EXPECT_TRUE(report.at("mesh").at("closed").get<bool>());

  const Result refused = run("skeletonize " + cloud + " --leaves l.ply -o s.ply", dir.root());
  EXPECT_EQ(refused.code, 2) << refused.out;
  EXPECT_NE(refused.out.find("needs --wood-only"), std::string::npos) << refused.out;
  EXPECT_FALSE(fs::exists(dir.path("s.ply")));

  const Result skeleton = run("skeletonize " + cloud + " --wood-only --leaves l.ply -o s.ply --json", dir.root());
  ASSERT_EQ(skeleton.code, 0) << skeleton.out;
  EXPECT_EQ(io::read_point_cloud(dir.path("l.ply")).size(), leaves);

  const Result batch = run("batch " + cloud + " -o out --wood-only --skeleton json", dir.root());
  ASSERT_EQ(batch.code, 0) << batch.out;
  EXPECT_EQ(io::read_point_cloud(dir.path("out/tree_arbor_leafy_leaves.ply")).size(), leaves);
  EXPECT_NE(batch.out.find(": " + std::to_string(wood) + " points (" + std::to_string(leaves) + " more set aside as leaves)"),
            std::string::npos) << batch.out;
  std::ifstream summary_in(dir.path("out/summary.json"));
  const auto summary = nlohmann::json::parse(summary_in);
  EXPECT_EQ(summary.at("trees").at(0).at("leaf_points"), leaves);
  EXPECT_EQ(summary.at("trees").at(0).at("points"), wood);
}

// --wood-if-leafy (plot's default for each tree): the leaves of the leafy tree set aside as --wood-only
// would; the leafless tree kept whole, its skeleton byte for byte the one without the option, and an
// empty cloud of leaves written; the report says what was estimated and decided.
TEST(Cli, WoodIfLeafySetsLeavesAsideFromALeafyCloudAlone) {
  const test::TempDir dir;
  const std::string leafy = quoted(test::data_file("tree_arbor_leafy.xyz"));
  const std::string leafless = quoted(test::data_file("tree_adtree1.xyz"));
  const auto report_of = [&](const std::string& file) {
    std::ifstream in(dir.path(file));
    return nlohmann::json::parse(in);
  };
  const Result r = run("skeletonize " + leafy + " --wood-if-leafy --leaves l.ply -o s.ply --report r.json", dir.root());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("--wood-if-leafy: the cloud looks leafy (about "), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("warning"), std::string::npos) << r.out;
  const auto report = report_of("r.json");
  EXPECT_TRUE(report.at("wood_if_leafy").at("leaves_set_aside").get<bool>());
  EXPECT_GE(report.at("wood_if_leafy").at("estimated_leaf_share").get<double>(), 0.16);
  const std::size_t leaves = report.at("wood_only").at("leaf_points");
  EXPECT_GT(leaves, 36478u / 6);
  EXPECT_EQ(io::read_point_cloud(dir.path("l.ply")).size(), leaves);
  EXPECT_TRUE(report.at("warnings").empty()) << report.at("warnings");
  // The same split as --wood-only's.
  ASSERT_EQ(run("skeletonize " + leafy + " --wood-only -o w.ply --report w.json", dir.root()).code, 0);
  EXPECT_EQ(report_of("w.json").at("wood_only"), report.at("wood_only"));
  EXPECT_EQ(text_of(dir.path("w.ply")), text_of(dir.path("s.ply")));

  const Result whole = run("skeletonize " + leafless + " --wood-if-leafy --leaves l2.ply -o s2.ply --report r2.json", dir.root());
  ASSERT_EQ(whole.code, 0) << whole.out;
  EXPECT_EQ(whole.out.find("--wood-if-leafy"), std::string::npos) << whole.out;
  const auto kept = report_of("r2.json");
  EXPECT_FALSE(kept.at("wood_if_leafy").at("leaves_set_aside").get<bool>());
  EXPECT_LT(kept.at("wood_if_leafy").at("estimated_leaf_share").get<double>(), 0.16);
  EXPECT_FALSE(kept.contains("wood_only"));
  EXPECT_EQ(kept.at("points"), 11855);
  EXPECT_NE(text_of(dir.path("l2.ply")).find("element vertex 0\n"), std::string::npos);  // a PLY of no points
  ASSERT_EQ(run("skeletonize " + leafless + " -o s3.ply", dir.root()).code, 0);
  EXPECT_EQ(text_of(dir.path("s2.ply")), text_of(dir.path("s3.ply")));

  const Result both = run("skeletonize " + leafy + " --wood-only --wood-if-leafy -o s4.ply", dir.root());
  EXPECT_EQ(both.code, 2) << both.out;
  EXPECT_NE(both.out.find("give one"), std::string::npos) << both.out;
  EXPECT_FALSE(fs::exists(dir.path("s4.ply")));
}

// Without --wood-only, a cloud that looks leafy is said to be, on stderr and in the report's
// warnings, by skeletonize and model; a leafless tree is not, nor a cloud whose leaves were set aside.
TEST(Cli, ALeafyCloudIsCalledLeafy) {
  const test::TempDir dir;
  const std::string leafy = quoted(test::data_file("tree_arbor_leafy.xyz"));
  const auto leafy_warnings = [&](const std::string& args) {
    const Result r = run(args + " --report r.json", dir.root());
    EXPECT_EQ(r.code, 0) << args << ": " << r.out;
    std::ifstream in(dir.path("r.json"));
    const auto report = nlohmann::json::parse(in);
    std::size_t count = 0;
    for (const auto& w : report.at("warnings")) {
      const std::string text = w.get<std::string>();
      if (text.find("looks leafy") == std::string::npos) continue;
      ++count;
      EXPECT_NE(text.find("--wood-only sets them aside"), std::string::npos) << text;  // the command's remedy
    }
    EXPECT_EQ(count > 0, r.out.find("looks leafy") != std::string::npos) << args << ": " << r.out;
    return count;
  };
  EXPECT_EQ(leafy_warnings("skeletonize " + leafy + " -o s.ply"), 1u);
  EXPECT_EQ(leafy_warnings("model " + leafy + " -o m.ply"), 1u);
  EXPECT_EQ(leafy_warnings("skeletonize " + leafy + " --wood-only -o s.ply"), 0u);
  EXPECT_EQ(leafy_warnings("skeletonize " + quoted(test::data_file("tree_adtree1.xyz")) + " -o s.ply"), 0u);
}

TEST(Cli, AnOutputThatIsASymbolicLinkStaysOne) {
  const test::TempDir dir;
  fs::create_directory(dir.path("real"));
  std::ofstream(dir.path("real/s.json")) << "old";
  fs::create_symlink("real/s.json", dir.path("s.json"));
  const Result r = run("skeletonize -o s.json -q", dir.root());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(fs::is_symlink(dir.path("s.json")));
  EXPECT_NE(text_of(dir.path("real/s.json")).find("treeskel skeleton"), std::string::npos);
  EXPECT_EQ(temporaries_in(dir.root()) + temporaries_in(dir.path("real")), 0);
}

// Usage errors exit with 2 at once, with messages a person can read.
TEST(Cli, UsageErrorsExitTwoBeforeAnyWork) {
  const test::TempDir dir;
  for (const std::string args : {"model --up w", "model -o x.fbx", "model --qsm q.txt", "model --min-segments 100",
                                 "model --breast-height -1", "skeletonize --root 1,2", "model --tension 2",
                                 "skeletonize -o x.stl", "model -o ."}) {
    const Result r = run(args, dir.root());
    EXPECT_EQ(r.code, 2) << args << ": " << r.out;
    EXPECT_LT(r.out.size(), 300u) << args << ": " << r.out;
    EXPECT_EQ(r.out.find("reading"), std::string::npos) << args << ": " << r.out;
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.root()), fs::directory_iterator()), 0);
}

}  // namespace
}  // namespace treeskel
