// End-to-end runs of `treeskel batch` on the bundled clouds, with broken inputs and a killed batch.
#include "run_tool.h"
#include "support/synthetic.h"
#include "treeskel/io/mesh_io.h"
#include "treeskel/io/skeleton_io.h"
#include "treeskel/modeling/tree_mesh.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

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

std::size_t lines_of(const std::string& path) {
  std::ifstream in(path);
  std::size_t n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

TEST(Batch, ConvertsAFolderAndEveryBrokenInputFailsAlone) {
  const test::TempDir dir;
  const std::string bundled = fs::path(test::data_file("tree_rtwig.txt")).parent_path().string();
  fs::create_directories(dir.path("bad"));
  std::ofstream(dir.path("bad/corrupt.xyz")) << "1.0 2.0 3.0\n4.0 five 6.0\n";
  std::ofstream(dir.path("bad/empty.xyz")).flush();
  const Result r = run("batch " + quoted(bundled) + " " + quoted(dir.path("bad")) + " -o " + quoted(dir.path("out")) + " -j 2");
  EXPECT_EQ(r.code, 1) << r.out;  // some failed
  // The bundled folder's licence and README are passed over, not failed.
  EXPECT_NE(r.out.find("do not look like point clouds"), std::string::npos) << r.out;
  const auto summary = read_json(dir.path("out/summary.json"));
  EXPECT_EQ(summary["inputs"], 5);
  EXPECT_EQ(summary["converted"], 3);
  EXPECT_EQ(summary["failed"], 2);
  EXPECT_EQ(lines_of(dir.path("out/summary.csv")), 6u);
  for (const auto& row : summary["trees"]) {
    const std::string name = row["name"];
    if (name == "corrupt" || name == "empty") {
      EXPECT_EQ(row["status"], "failed");
      EXPECT_NE(row["error"].get<std::string>().find(name == "empty" ? "empty" : "line 2"), std::string::npos) << row;
      EXPECT_FALSE(fs::exists(dir.path("out/" + name + ".glb")));
      continue;
    }
    EXPECT_EQ(row["status"], "ok") << row;
    EXPECT_EQ(row["points"], name == "tree_rtwig" ? 14667 : name == "tree_arbor_leafy" ? 36478 : 11855);
    EXPECT_GT(row["height"].get<double>(), 3.0);
    EXPECT_GT(row["skeleton_coverage"].get<double>(), 0.95);
    // The model as the summary says: re-read, closed, the same triangles.
    const modeling::TreeMesh mesh = io::read_mesh(dir.path("out/" + name + ".glb"));
    const modeling::MeshCheck check = modeling::check_mesh(mesh, false);
    EXPECT_EQ(check.boundary_edges, 0u) << name;
    EXPECT_EQ(check.faces, row["triangles"].get<std::size_t>()) << name;
  }
}

TEST(Batch, ResumeAfterAKilledBatchRedoesNothingComplete) {
  const test::TempDir dir;
  fs::create_directories(dir.path("in"));
  fs::copy_file(test::data_file("tree_rtwig.txt"), dir.path("in/fast.txt"));  // the largest file: first
  fs::copy_file(test::data_file("tree_adtree1.xyz"), dir.path("in/slow.xyz"));
  fs::copy_file(test::data_file("tree_adtree1.xyz"), dir.path("in/later.xyz"));
  const std::string batch = "batch " + quoted(dir.path("in")) + " -o " + quoted(dir.path("out")) + " -j 2";
  // In a process group of its own, as a scheduler would start it, then killed with all it started.
  // Its temporary folder is the test's, to see that the kill leaves nothing there either.
  fs::create_directories(dir.path("tmp"));
  const std::string start = "cd " + quoted(dir.root()) + " && TMPDIR=" + quoted(dir.path("tmp")) + " setsid '" TREESKEL_EXE "' " + batch +
                            " >batch.log 2>&1 & echo $! > " + quoted(dir.path("pid"));
  ASSERT_EQ(std::system(start.c_str()), 0);
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (!fs::exists(dir.path("out/fast_report.json")) && std::chrono::steady_clock::now() < give_up)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_TRUE(fs::exists(dir.path("out/fast_report.json")));
  pid_t pid = 0;
  std::ifstream(dir.path("pid")) >> pid;
  ASSERT_GT(pid, 0);
  ASSERT_EQ(::kill(-pid, SIGKILL), 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  // The tree in flight left nothing half-written.
  EXPECT_FALSE(fs::exists(dir.path("out/slow_report.json")));
  EXPECT_FALSE(fs::exists(dir.path("out/slow.glb")));
  // The processes' logs had no names: nothing of them is left in the temporary folder.
  EXPECT_TRUE(fs::is_empty(dir.path("tmp")));
  const auto fast_written = fs::last_write_time(dir.path("out/fast.glb"));

  const Result r = run(batch + " --resume");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(fs::last_write_time(dir.path("out/fast.glb")), fast_written);  // not redone
  const auto summary = read_json(dir.path("out/summary.json"));
  EXPECT_EQ(summary["converted"], 3);
  for (const auto& row : summary["trees"]) {
    EXPECT_EQ(row["status"], "ok") << row;
    EXPECT_EQ(row["resumed"], row["name"] == "fast") << row;
    for (const auto& out : row["outputs"]) EXPECT_TRUE(fs::exists(out.get<std::string>())) << out;
  }
  // No staging folder of the killed run is left in the output folder.
  for (const auto& e : fs::directory_iterator(dir.path("out")))
    EXPECT_NE(e.path().filename().string().rfind(".treeskel", 0), 0u) << e.path();
}

TEST(Batch, SkeletonsOnlyAndOneShardOfAnArrayJob) {
  const test::TempDir dir;
  fs::create_directories(dir.path("in"));
  for (const char* name : {"a.txt", "b.txt", "c.txt"}) fs::copy_file(test::data_file("tree_rtwig.txt"), dir.path(std::string("in/") + name));
  const Result r = run("batch " + quoted(dir.path("in")) + " -o " + quoted(dir.path("out")) + " --skeleton json --shard 1/2");
  ASSERT_EQ(r.code, 0) << r.out;
  // Shard 1 of 2 takes the second of a, b, c.
  EXPECT_TRUE(fs::exists(dir.path("out/b_skeleton.json")));
  EXPECT_FALSE(fs::exists(dir.path("out/a_skeleton.json")));
  EXPECT_FALSE(fs::exists(dir.path("out/c_skeleton.json")));
  EXPECT_FALSE(fs::exists(dir.path("out/b.glb")));  // skeletons only
  const Skeleton s = io::read_skeleton(dir.path("out/b_skeleton.json"));
  const auto summary = read_json(dir.path("out/summary-1-of-2.json"));
  ASSERT_EQ(summary["trees"].size(), 1u);
  EXPECT_EQ(summary["trees"][0]["nodes"].get<std::size_t>(), s.node_count());
  // Pruned as skeletonize prunes, not as the model defaults --help shows: the same skeleton.
  const Result direct = run("skeletonize " + quoted(dir.path("in/b.txt")) + " -o " + quoted(dir.path("b.json")) + " -q");
  ASSERT_EQ(direct.code, 0) << direct.out;
  EXPECT_EQ(io::read_skeleton(dir.path("b.json")).node_count(), s.node_count());
  // An option of the model without a model is a usage error, before any work.
  const Result wrong = run("batch " + quoted(dir.path("in")) + " -o " + quoted(dir.path("out2")) + " --skeleton json --exponent 2.5");
  EXPECT_EQ(wrong.code, 2) << wrong.out;
  EXPECT_NE(wrong.out.find("--exponent"), std::string::npos) << wrong.out;
}

}  // namespace
}  // namespace treeskel
