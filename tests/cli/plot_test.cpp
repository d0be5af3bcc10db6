// End-to-end runs of `treeskel plot`: two of the bundled trees side by side in UTM coordinates give two
// models; a synthetic plot is segmented; a cloud with no stem and a bad option fail clearly.
#include "run_tool.h"
#include "support/synthetic.h"
#include "treeskel/eval/plots.h"
#include "treeskel/io/mesh_io.h"
#include "treeskel/io/point_cloud_io.h"
#include "treeskel/modeling/tree_mesh.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <cstring>
#include <memory>
#include <random>
#include <set>

namespace treeskel {
namespace {

namespace fs = std::filesystem;

using test::quoted;
using test::Result;
using test::run;

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(Plot, TwoTreesSideBySideGiveTwoModelsInTheInputsFrame) {
  const test::TempDir dir;
  PointCloud tree = io::read_point_cloud(test::data_file("tree_adtree1.xyz"));
  PointCloud two;
  const Eigen::Vector3d utm(500000.0, 5000000.0, 100.0);
  for (double shift : {0.0, 10.0})
    for (const auto& p : tree.positions) two.positions.push_back(p + tree.offset + utm + Eigen::Vector3d(shift, 0, 0));
  recentre_offset(two);
  io::write_point_cloud(dir.path("two.ply"), two);

  // --local (a model option, passed on to each tree): meshes in the tree's own frame, which assimp
  // (single precision) re-reads exactly.
  const Result r = run("plot " + quoted(dir.path("two.ply")) + " -o " + quoted(dir.path("out")) + " --local");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("2 trees, 2 modelled"), std::string::npos) << r.out;
  const auto doc = read_json(dir.path("out/trees.json"));
  ASSERT_EQ(doc["trees"].size(), 2u) << doc;
  EXPECT_EQ(doc["points"], 2 * tree.size());
  std::size_t in_trees = 0;
  for (int t = 0; t < 2; ++t) {
    const auto& row = doc["trees"][t];
    EXPECT_EQ(row["status"], "ok") << row;
    EXPECT_EQ(row["id"], t + 1);
    // The bundled tree's trunk stands near (-0.77, 18.26) in its file; the stems are written in the
    // input's frame.
    EXPECT_NEAR(row["x"].get<double>(), utm.x() - 0.77 + 10.0 * t, 0.05) << row;
    EXPECT_NEAR(row["y"].get<double>(), utm.y() + 18.26, 0.05) << row;
    EXPECT_GT(row["points"].get<std::size_t>(), tree.size() * 95 / 100);
    in_trees += row["points"].get<std::size_t>();
    EXPECT_NEAR(row["height"].get<double>(), 5.5, 0.3);
    EXPECT_NEAR(row["dbh"].get<double>(), 0.18, 0.03);
    EXPECT_GT(row["skeleton_coverage"].get<double>(), 0.95);
    // The model's warnings, as its report has them.
    char report[64];
    std::snprintf(report, sizeof report, "out/trees/tree_%03d_report.json", t + 1);
    EXPECT_EQ(row["warnings"], read_json(dir.path(report))["warnings"]) << row;
    // The model, re-read: closed.
    const modeling::TreeMesh mesh = io::read_mesh(dir.path("out/" + row["model"].get<std::string>()));
    EXPECT_EQ(modeling::check_mesh(mesh, false).boundary_edges, 0u);
  }
  EXPECT_EQ(in_trees, doc["tree_points"].get<std::size_t>());
  // The labelled cloud: every point, with its tree.
  const PointCloud labelled = io::read_point_cloud(dir.path("out/labelled.ply"));
  EXPECT_EQ(labelled.size(), two.size());
  EXPECT_NE(read_text(dir.path("out/labelled.ply")).find("property uint tree_id\nproperty uchar class\nproperty float height"),
            std::string::npos);
  EXPECT_EQ(read_text(dir.path("out/plan.png")).substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(std::count(std::istreambuf_iterator<char>(*std::make_unique<std::ifstream>(dir.path("out/trees.csv"))), {}, '\n'), 3);
  const std::string csv = read_text(dir.path("out/trees.csv"));
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "id,name,x,y,ground_z,points,leaf_points,height,crown_base,stem_dbh,dbh,volume,skeleton_coverage,status,warnings,"
            "model,error");

  // Again with --resume: the same trees, so their models are kept, not made again.
  const Result again = run("plot " + quoted(dir.path("two.ply")) + " -o " + quoted(dir.path("out")) + " --local --resume");
  ASSERT_EQ(again.code, 0) << again.out;
  EXPECT_NE(again.out.find("2 inputs: 2 converted (2 before this run)"), std::string::npos) << again.out;
  EXPECT_EQ(read_json(dir.path("out/trees.json"))["trees"], doc["trees"]);

  // A model option that makes each model warn (the trees are 5.5 m tall): the table carries it.
  const Result tall = run("plot " + quoted(dir.path("two.ply")) + " -o " + quoted(dir.path("tall")) + " --local --breast-height 6");
  ASSERT_EQ(tall.code, 0) << tall.out;
  const auto warned = read_json(dir.path("tall/trees.json"));
  ASSERT_EQ(warned["trees"].size(), 2u);
  const std::string first = warned["trees"][0]["warnings"].at(0).get<std::string>();
  EXPECT_NE(first.find("breast height"), std::string::npos) << first;
  const std::string table = read_text(dir.path("tall/trees.csv"));
  EXPECT_NE(table.find("breast height", table.find('\n')), std::string::npos) << table;
}

// A real tree in leaf (arbor's, every fourth point) beside a leafless one: by default the leafy tree
// is modelled from its wood, its leaves written beside it and counted in the table; the leafless one
// whole, with a cloud of no leaves. --keep-leaves models both whole and removes the earlier leaves.
TEST(Plot, ALeafyTreeIsModelledFromItsWood) {
  const test::TempDir dir;
  const PointCloud leafy = io::read_point_cloud(test::data_file("tree_arbor_leafy.xyz"));
  const PointCloud leafless = io::read_point_cloud(test::data_file("tree_adtree1.xyz"));
  PointCloud two;
  const auto place = [&](const PointCloud& tree, const Eigen::Vector3d& at) {
    const Eigen::AlignedBox3d box = bounding_box(tree);
    const Eigen::Vector3d foot(box.center().x(), box.center().y(), box.min().z());
    for (const auto& p : tree.positions) two.positions.push_back(p - foot + at);
  };
  place(leafy, Eigen::Vector3d(500000.0, 5000000.0, 100.0));
  place(leafless, Eigen::Vector3d(500008.0, 5000000.0, 100.0));
  recentre_offset(two);
  io::write_point_cloud(dir.path("two.ply"), two);

  const Result r = run("plot " + quoted(dir.path("two.ply")) + " -o " + quoted(dir.path("out")) + " --local");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto doc = read_json(dir.path("out/trees.json"));
  ASSERT_EQ(doc["trees"].size(), 2u) << doc;
  const auto& in_leaf = doc["trees"][0];  // the ids go west to east
  const auto& bare = doc["trees"][1];
  ASSERT_EQ(in_leaf["status"], "ok") << in_leaf;
  ASSERT_EQ(bare["status"], "ok") << bare;
  EXPECT_NE(r.out.find("2 modelled (1 of them from their wood alone"), std::string::npos) << r.out;
  const std::size_t leaves = in_leaf["leaf_points"].get<std::size_t>();
  EXPECT_GT(leaves, in_leaf["points"].get<std::size_t>() / 6) << in_leaf;
  EXPECT_LT(leaves, in_leaf["points"].get<std::size_t>() / 3) << in_leaf;
  EXPECT_EQ(io::read_point_cloud(dir.path("out/trees/tree_001_leaves.ply")).size(), leaves);
  const auto report = read_json(dir.path("out/trees/tree_001_report.json"));
  EXPECT_TRUE(report["wood_if_leafy"]["leaves_set_aside"].get<bool>());
  EXPECT_EQ(report["points"].get<std::size_t>() + leaves, in_leaf["points"].get<std::size_t>());
  EXPECT_EQ(bare["leaf_points"], 0) << bare;
  EXPECT_NE(read_text(dir.path("out/trees/tree_002_leaves.ply")).find("element vertex 0\n"), std::string::npos);
  EXPECT_FALSE(read_json(dir.path("out/trees/tree_002_report.json"))["wood_if_leafy"]["leaves_set_aside"].get<bool>());
  const std::string csv = read_text(dir.path("out/trees.csv"));
  EXPECT_NE(csv.find("," + std::to_string(in_leaf["points"].get<std::size_t>()) + "," + std::to_string(leaves) + ","),
            std::string::npos) << csv;

  const Result whole = run("plot " + quoted(dir.path("two.ply")) + " -o " + quoted(dir.path("out")) + " --local --keep-leaves");
  ASSERT_EQ(whole.code, 0) << whole.out;
  EXPECT_EQ(whole.out.find("from their wood alone"), std::string::npos) << whole.out;
  const auto kept = read_json(dir.path("out/trees.json"));
  ASSERT_EQ(kept["trees"].size(), 2u);
  for (const auto& row : kept["trees"]) EXPECT_EQ(row["leaf_points"], 0) << row;
  EXPECT_FALSE(fs::exists(dir.path("out/trees/tree_001_leaves.ply")));
  EXPECT_FALSE(fs::exists(dir.path("out/trees/tree_002_leaves.ply")));
  EXPECT_EQ(read_json(dir.path("out/trees/tree_001_report.json"))["points"], in_leaf["points"]);
  // The leafy tree's model, made of its leaves too, now warns that it looks leafy.
  EXPECT_NE(kept["trees"][0]["warnings"].dump().find("looks leafy"), std::string::npos) << kept["trees"][0];

  // As PLY, the models are named apart from the trees' clouds (tree_NNN.ply), which stay as they were.
  const std::string cloud_before = read_text(dir.path("out/trees/tree_002.ply"));
  const Result ply = run("plot " + quoted(dir.path("two.ply")) + " -o " + quoted(dir.path("out")) + " --local --model ply");
  ASSERT_EQ(ply.code, 0) << ply.out;
  EXPECT_EQ(read_json(dir.path("out/trees.json"))["trees"][1]["model"], "trees/tree_002_mesh.ply");
  EXPECT_EQ(read_text(dir.path("out/trees/tree_002.ply")), cloud_before);
  EXPECT_EQ(modeling::check_mesh(io::read_mesh(dir.path("out/trees/tree_002_mesh.ply")), false).boundary_edges, 0u);

  const Result both = run("plot " + quoted(dir.path("two.ply")) + " -o " + quoted(dir.path("x")) + " --keep-leaves --wood-only");
  EXPECT_EQ(both.code, 2) << both.out;
  EXPECT_NE(both.out.find("give one"), std::string::npos) << both.out;
}

// The bundled LPine1 plot segmented once (each tree's points in trees/tree_NNN.ply), for the tests
// that model its trees.
class LPine1Plot : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<test::TempDir>();
    const Result seg = run("plot " + quoted(TREESKEL_TEST_LAZ) + " -o " + quoted(dir_->path("out")) + " --segment-only");
    ASSERT_EQ(seg.code, 0) << seg.out;
  }
  static void TearDownTestSuite() { dir_.reset(); }
  /// Tree `id` ("004") of the plot, as a cloud file.
  static std::string tree(const std::string& id) { return dir_->path("out/trees/tree_" + id + ".ply"); }
  /// The `mesh` part of the report `treeskel model` writes for tree `id` (null, with a failure, if
  /// the tree or the model is missing).
  nlohmann::json model_mesh(const std::string& id) const {
    if (!fs::exists(tree(id))) {
      ADD_FAILURE() << "no tree " << id;
      return nullptr;
    }
    const Result r = run("model " + quoted(tree(id)) + " -q -o " + quoted(dir.path("t.glb")) + " --report " + quoted(dir.path("r.json")));
    if (r.code != 0) {
      ADD_FAILURE() << r.out;
      return nullptr;
    }
    return read_json(dir.path("r.json"))["mesh"];
  }
  const test::TempDir dir;  // this test's own outputs
 private:
  static std::unique_ptr<test::TempDir> dir_;
};
std::unique_ptr<test::TempDir> LPine1Plot::dir_;

// A branch the sweep re-attached to a thicker one is swept once. On tree 11 of the bundled LPine1
// plot an 8,614-node limb went both into the tree's mesh and into a piece swept apart (the pieces
// were cut from the skeleton as it was before the re-attachment); the copies crossed each other once
// rounded to floats wherever a union cut them, and the unions were thrown away and redone 186 times
// (406 s, 979,894 triangles). Now one union takes it in (254,754 triangles then). (9 unions in all
// with the skeleton's path, 13 with the limbs straightened, the default since 6 December 2026, and 18
// with stubs and the exact bound on a stem fork's shares, the same day: 143,894 triangles; 25 with
// a model's pruning at one radius, later that day: 188,458 triangles; 22 and 186,410 with stubs of
// 6.5 radii.)
TEST_F(LPine1Plot, ALimbOfAPineIsSweptOnce) {
  const auto mesh = model_mesh("011");
  ASSERT_TRUE(mesh.is_object());
  EXPECT_LE(mesh["unions"].get<int>(), 30) << mesh.dump();
  EXPECT_LT(mesh["triangles"].get<int>(), 400000) << mesh.dump();
  EXPECT_EQ(mesh["pieces_failed"].get<int>(), 0) << mesh.dump();
  EXPECT_GE(mesh["skeleton_coverage"].get<double>(), 0.97) << mesh.dump();
}

// No limb is left out for want of corefinements: the union's budget is one a piece where there are
// more than 48 pieces. Tree 10 of the plot, pruned as a model prunes, had 138 limbs to unite and
// needed 57 corefinements (56 now); under a flat budget of 48, 67 limbs were left out and the mesh
// held 37% of the skeleton.
TEST_F(LPine1Plot, EveryLimbOfACrowdedPineIsUnited) {
  const auto mesh = model_mesh("010");
  ASSERT_TRUE(mesh.is_object());
  EXPECT_GT(mesh["unions"].get<int>(), 48) << mesh.dump();
  EXPECT_EQ(mesh["pieces_failed"].get<int>(), 0) << mesh.dump();
  EXPECT_EQ(mesh["components"].get<int>(), 1) << mesh.dump();
  EXPECT_GE(mesh["skeleton_coverage"].get<double>(), 0.97) << mesh.dump();
}

// The same model for one thread and two. On tree 4 of the bundled LPine1 plot, two runs in five on
// two threads wrote another GLB (15 triangles of one join): CGAL's convex hull split a flat face of
// the join in an order that followed memory addresses, and which thread had run what before moved
// them. (A run that differs only sometimes: three runs on two threads.)
TEST_F(LPine1Plot, TreesAreOneComponentAndTheSameOnOneThreadAndTwo) {
  ASSERT_TRUE(fs::exists(tree("004")));
  auto model = [&](int threads, const std::string& name) {
    const Result r = run("--threads " + std::to_string(threads) + " model " + quoted(tree("004")) + " --wood-if-leafy -q -o " + quoted(dir.path(name)));
    EXPECT_EQ(r.code, 0) << r.out;
    return read_text(dir.path(name));
  };
  const std::string one = model(1, "one.glb");
  ASSERT_GT(one.size(), 100000u);
  for (int run_no = 0; run_no < 3; ++run_no) EXPECT_TRUE(model(2, "two.glb") == one) << "run " << run_no;
  // Trees 4 and 13 each had a limb beside the tree, a second component: a branch that ran back along
  // its parent from a fork 2 mm inside the parent's tube, and a fork 2.4 cm outside a thinned one.
  for (const std::string id : {"004", "013"}) {
    const std::string report = dir.path("r" + id + ".json");
    const Result r = run("model " + quoted(tree(id)) + " --wood-if-leafy -q -o " +
                         quoted(dir.path("t.glb")) + " --report " + quoted(report));
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(read_json(report)["mesh"]["components"].get<int>(), 1) << "tree " << id;
  }
}

TEST(Plot, ASyntheticPlotSegmentedOnly) {
  const test::TempDir dir;
  eval::PlotOptions o;
  o.trees = 3;
  o.width = 9.0;
  o.shrubs = 3;
  o.points_per_tree = 8000;
  const eval::SyntheticPlot plot = eval::make_plot(o);
  io::write_point_cloud(dir.path("plot.ply"), plot.cloud);
  // What an earlier run with other results left: a tree this run does not find, a tree whose cloud
  // was another, and a file of the user's.
  fs::create_directories(dir.path("out/trees"));
  for (const char* old : {"tree_009.ply", "tree_009.glb", "tree_009_report.json", "tree_001.ply", "tree_001.glb",
                          "tree_001_skeleton.json", "notes.txt"})
    std::ofstream(dir.path("out/trees/") + old) << "from before\n";
  const Result r = run("plot " + quoted(dir.path("plot.ply")) + " -o " + quoted(dir.path("out")) + " --segment-only");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto doc = read_json(dir.path("out/trees.json"));
  ASSERT_EQ(doc["trees"].size(), 3u) << r.out;
  for (const auto& row : doc["trees"]) {
    EXPECT_EQ(row["status"], "segmented");
    EXPECT_TRUE(row["model"].is_null());
    EXPECT_TRUE(fs::exists(dir.path("out/trees/" + row["name"].get<std::string>() + ".ply")));
  }
  for (const char* stale : {"tree_009.ply", "tree_009.glb", "tree_009_report.json", "tree_001.glb", "tree_001_skeleton.json"})
    EXPECT_FALSE(fs::exists(dir.path("out/trees/") + stale)) << stale;
  EXPECT_TRUE(fs::exists(dir.path("out/trees/notes.txt")));
  EXPECT_GT(fs::file_size(dir.path("out/trees/tree_001.ply")), 1000u);
  EXPECT_GT(doc["ground_points"].get<std::size_t>(), 0u);

  // The same plot as LAS with its ground classified (class 2): the classification is the ground.
  PointCloud classified = plot.cloud;
  classified.classes.resize(classified.size());
  std::size_t true_ground = 0;
  for (std::size_t p = 0; p < classified.size(); ++p) {
    classified.classes[p] = plot.kind[p] == eval::PointKind::ground ? 2 : 1;
    true_ground += classified.classes[p] == 2;
  }
  io::write_point_cloud(dir.path("plot.las"), classified);
  fs::create_directories(dir.path("las"));
  std::ofstream(dir.path("las/labelled.ply")) << "from an earlier run\n";
  const Result las = run("plot " + quoted(dir.path("plot.las")) + " -o " + quoted(dir.path("las")) + " --segment-only --labelled las");
  ASSERT_EQ(las.code, 0) << las.out;
  EXPECT_NE(las.out.find("the file's classification"), std::string::npos) << las.out;
  const auto from_las = read_json(dir.path("las/trees.json"));
  EXPECT_EQ(from_las["trees"].size(), 3u);
  // Ground points are the classified ones, less the stems' bases.
  EXPECT_LE(from_las["ground_points"].get<std::size_t>(), true_ground);
  EXPECT_GT(from_las["ground_points"].get<std::size_t>(), true_ground * 99 / 100);

  // The labelled cloud as LAS: the input's classes kept, tree_id as extra bytes after each point's
  // 20 bytes (format 0), as many points in trees as the table says; the earlier PLY is gone.
  EXPECT_EQ(from_las["outputs"]["labelled"], "labelled.las");
  EXPECT_FALSE(fs::exists(dir.path("las/labelled.ply")));
  const PointCloud labelled = io::read_point_cloud(dir.path("las/labelled.las"));
  EXPECT_EQ(labelled.classes, classified.classes);
  const std::string f = read_text(dir.path("las/labelled.las"));
  std::uint32_t first = 0, id = 0;
  std::uint16_t record = 0;
  std::memcpy(&first, f.data() + 96, 4);
  std::memcpy(&record, f.data() + 105, 2);
  ASSERT_EQ(record, 20 + 9);
  ASSERT_EQ(f.size(), first + classified.size() * record);
  std::size_t in_trees = 0;
  std::set<std::uint32_t> ids;
  for (std::size_t p = 0; p < classified.size(); ++p) {
    std::memcpy(&id, f.data() + first + p * record + 20, 4);
    in_trees += id != 0;
    if (id) ids.insert(id);
  }
  EXPECT_EQ(in_trees, from_las["tree_points"].get<std::size_t>());
  EXPECT_EQ(ids, (std::set<std::uint32_t>{1, 2, 3}));
}

TEST(Plot, NoStemAndBadOptionsFailClearly) {
  const test::TempDir dir;
  PointCloud blob;
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0.0, 3.0);
  for (int i = 0; i < 3000; ++i) blob.positions.emplace_back(u(rng), u(rng), u(rng));
  io::write_point_cloud(dir.path("blob.xyz"), blob);
  const Result none = run("plot " + quoted(dir.path("blob.xyz")) + " -o " + quoted(dir.path("out")));
  EXPECT_EQ(none.code, 1) << none.out;
  EXPECT_NE(none.out.find("no stem found"), std::string::npos) << none.out;
  EXPECT_TRUE(fs::exists(dir.path("out/plan.png")));  // to see why
  const Result bad = run("plot " + quoted(dir.path("blob.xyz")) + " -o " + quoted(dir.path("out")) + " --stem-slice 2,1");
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_NE(bad.out.find("--stem-slice 2,1"), std::string::npos) << bad.out;
  const Result format = run("plot " + quoted(dir.path("blob.xyz")) + " -o " + quoted(dir.path("out")) + " --labelled xyz");
  EXPECT_EQ(format.code, 2) << format.out;
  EXPECT_NE(format.out.find("--labelled xyz"), std::string::npos) << format.out;
  const Result missing = run("plot " + quoted(dir.path("nothing.xyz")) + " -o " + quoted(dir.path("out2")));
  EXPECT_EQ(missing.code, 1) << missing.out;
  EXPECT_NE(missing.out.find("nothing.xyz"), std::string::npos) << missing.out;
}

}  // namespace
}  // namespace treeskel
