// The planning of `treeskel batch`: which files a command line names, under which output names, and
// which of them a shard takes.
#include "batch_plan.h"
#include "support/synthetic.h"
#include "treeskel/error.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>

namespace treeskel::cli {
namespace {

namespace fs = std::filesystem;

void write(const std::string& path, const std::string& text) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream(path) << text;
}

const std::vector<std::string> kExtensions{"xyz", "txt", "las", "ply"};

TEST(BatchPlan, FoldersAreSearchedAndNameTheOutputsByTheirPathBelow) {
  const test::TempDir dir;
  write(dir.path("plot/a.xyz"), "1 2 3\n");
  write(dir.path("plot/row2/b.txt"), "# a comment\nX,Y,Z,intensity\n1,2,3,4\n");
  write(dir.path("plot/LICENSE.txt"), "Permission is granted to anyone\n");  // not a cloud
  write(dir.path("plot/qsm.txt"), "radius,length,start_x\n0.1,1,0\n");     // a table of other columns
  write(dir.path("plot/notes.md"), "1 2 3\n");                              // not an extension of clouds
  write(dir.path("plot/fake.ply"), "1 2 3\n");                              // a .ply that is no PLY
  write(dir.path("plot/.hidden/c.xyz"), "1 2 3\n");
  write(dir.path("plot/out/old.xyz"), "1 2 3\n");  // the output folder, inside the input's
  write(dir.path("plot/scan7.xyz"), "");            // empty: taken, to fail with a message
  std::vector<fs::path> passed_over;
  const auto inputs = plan_inputs({dir.path("plot")}, kExtensions, dir.path("plot/out"), &passed_over);
  ASSERT_EQ(inputs.size(), 3u);
  EXPECT_EQ(inputs[0].name, fs::path("a"));
  EXPECT_EQ(inputs[1].name, fs::path("row2/b"));
  EXPECT_EQ(inputs[2].name, fs::path("scan7"));
  for (const auto& in : inputs) EXPECT_EQ(in.error, "");
  std::set<std::string> over;
  for (const auto& p : passed_over) over.insert(p.filename().string());
  EXPECT_EQ(over, (std::set<std::string>{"LICENSE.txt", "fake.ply", "qsm.txt"}));
}

TEST(BatchPlan, FilesPatternsAndWhatIsNotThere) {
  const test::TempDir dir;
  write(dir.path("t1.xyz"), "1 2 3\n");
  write(dir.path("t2.xyz"), "1 2 3\n");
  write(dir.path("readme.txt"), "words\n");  // named: taken whatever it holds
  const auto inputs = plan_inputs({dir.path("t*.xyz"), dir.path("readme.txt"), dir.path("t1.xyz"), dir.path("gone.xyz"),
                                   dir.path("none*.las")},
                                  kExtensions);
  ASSERT_EQ(inputs.size(), 5u);  // t1 once, though named twice
  std::map<std::string, std::string> error;
  for (const auto& in : inputs) error[in.name.string()] = in.error;
  EXPECT_EQ(error.at("t1"), "");
  EXPECT_EQ(error.at("t2"), "");
  EXPECT_EQ(error.at("readme"), "");
  EXPECT_EQ(error.at("gone"), "no such file or folder");
  EXPECT_EQ(error.at("none*"), "no file matches this pattern");
}

TEST(BatchPlan, ClashingNamesTakeTheirExtensionOrAreRefused) {
  const test::TempDir dir;
  write(dir.path("a/tree.xyz"), "1 2 3\n");
  write(dir.path("a/tree.las"), "LASF");
  write(dir.path("b/tree.xyz"), "1 2 3\n");
  const auto inputs = plan_inputs({dir.path("a/tree.xyz"), dir.path("a/tree.las"), dir.path("b/tree.xyz")}, kExtensions);
  ASSERT_EQ(inputs.size(), 3u);
  EXPECT_EQ(inputs[0].name, fs::path("tree_las"));
  EXPECT_EQ(inputs[0].error, "");
  EXPECT_EQ(inputs[1].name, fs::path("tree_xyz"));
  EXPECT_EQ(inputs[1].error, "");
  EXPECT_NE(inputs[2].error.find("which " + dir.path("a/tree.xyz") + " has"), std::string::npos) << inputs[2].error;
}

TEST(BatchPlan, ShardsTakeEveryNthAndTogetherTakeAll) {
  std::vector<BatchInput> all(10);
  for (std::size_t i = 0; i < all.size(); ++i) all[i].name = std::to_string(i);
  std::size_t total = 0;
  for (std::size_t i = 0; i < 3; ++i) {
    const auto mine = take_shard(all, parse_shard(std::to_string(i) + "/3"));
    for (std::size_t k = 0; k < mine.size(); ++k) EXPECT_EQ(mine[k].name, fs::path(std::to_string(i + 3 * k)));
    total += mine.size();
  }
  EXPECT_EQ(total, all.size());
  EXPECT_EQ(take_shard(all, parse_shard("0/1")).size(), all.size());
  for (const char* bad : {"3/3", "1/0", "1", "/3", "a/3", "-1/3", "1/3/4", ""}) EXPECT_THROW(parse_shard(bad), OptionError) << bad;
}

TEST(BatchPlan, CsvFieldsAreQuotedWhereTheyMustBe) {
  EXPECT_EQ(csv_field("plain text"), "plain text");
  EXPECT_EQ(csv_field("a, b"), "\"a, b\"");
  EXPECT_EQ(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(csv_field("two\nlines"), "\"two\nlines\"");
  EXPECT_EQ(csv_field(""), "");
}

}  // namespace
}  // namespace treeskel::cli
