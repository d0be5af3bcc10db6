#include "treeskel/eval/paper_trees.h"

#include <gtest/gtest.h>

namespace treeskel::eval {
namespace {

TEST(PaperTrees, ExactCountsOfBranchPointsAndEndpoints) {
  for (std::uint64_t seed : {1u, 2u, 7u})
    for (const auto& spec : paper_tree_specs()) {
      const GroundTruth t = make_paper_tree(spec.index, seed);
      EXPECT_TRUE(is_tree(t.skeleton.graph));
      EXPECT_EQ(count_branch_points(t.skeleton.graph), static_cast<std::size_t>(spec.branch_points)) << spec.index;
      EXPECT_EQ(count_endpoints(t.skeleton.graph), static_cast<std::size_t>(spec.endpoints)) << spec.index;
      EXPECT_EQ(boost::degree(t.skeleton.root, t.skeleton.graph), 1u);
    }
}

TEST(PaperTrees, NormalisedWithTaperingLeonardoRadii) {
  const GroundTruth t = make_paper_tree(4, 1);
  Eigen::AlignedBox3d box;
  for (const auto& c : t.cylinders) {
    box.extend(c.a - Eigen::Vector3d::Constant(c.radius_a));
    box.extend(c.a + Eigen::Vector3d::Constant(c.radius_a));
    EXPECT_GT(c.radius_b, 0.0);
    EXPECT_LE(c.radius_b, c.radius_a + 1e-15);  // never thicker toward the tips
  }
  EXPECT_NEAR(box.sizes().maxCoeff(), 1.0, 0.02);
  // Leonardo at every fork: the square of the radius ending at the fork is the sum of the squares of
  // the radii starting there.
  const auto& s = t.skeleton;
  for (NodeId v = 0; v < s.node_count(); ++v) {
    if (boost::degree(v, s.graph) < 3) continue;
    double children = 0.0;
    for (const auto& c : t.cylinders)
      if ((c.a - s[v].position).norm() < 1e-12) children += c.radius_a * c.radius_a;
    EXPECT_NEAR(children, s[v].radius * s[v].radius, 1e-9);
  }
}

TEST(PaperTrees, SeventyTwoCloudsWithThePapersNames) {
  std::vector<std::string> names;
  for (int t = 1; t <= 6; ++t) {
    const GroundTruth truth = make_paper_tree(t, 1);
    for (const auto& c : make_paper_clouds(truth, t, 1)) {
      names.push_back(c.name);
      EXPECT_GT(c.cloud.size(), 5000u) << c.name;
    }
  }
  ASSERT_EQ(names.size(), 72u);
  EXPECT_EQ(names[0], "tree1_14045");
  EXPECT_EQ(names[1], "tree1_28189");
  EXPECT_EQ(names[2], "tree1_7088");
  EXPECT_EQ(names[3], "tree1_missing_1");
  EXPECT_EQ(names[8], "tree1_noise_3");
  EXPECT_EQ(names[11], "tree1_vdensity_3");
  EXPECT_EQ(names[50], "tree5_45680");
}

TEST(PaperTrees, CleanCloudsLieOnTheSurface) {
  const GroundTruth truth = make_paper_tree(2, 3);
  const auto clouds = make_paper_clouds(truth, 2, 3);
  const PointCloud& clean = clouds[0].cloud;
  ASSERT_EQ(clean.size(), 16647u);
  for (std::size_t i = 0; i < clean.size(); i += 7) {
    double best = 1e9;
    for (const auto& c : truth.cylinders) {
      const double t = std::clamp((clean.positions[i] - c.a).dot(c.b - c.a) / (c.b - c.a).squaredNorm(), 0.0, 1.0);
      best = std::min(best, std::abs(distance_to_axis(c, clean.positions[i]) - (c.radius_a + t * (c.radius_b - c.radius_a))));
    }
    EXPECT_LT(best, 1e-9);
  }
}

TEST(PaperTrees, SameSeedSameBytes) {
  const GroundTruth a = make_paper_tree(6, 11), b = make_paper_tree(6, 11);
  const auto ca = make_paper_clouds(a, 6, 11), cb = make_paper_clouds(b, 6, 11);
  for (std::size_t i = 0; i < ca.size(); ++i) EXPECT_EQ(ca[i].cloud.positions, cb[i].cloud.positions) << ca[i].name;
  EXPECT_NE(make_paper_tree(6, 12).cylinders.front().b, a.cylinders.front().b);
}

}  // namespace
}  // namespace treeskel::eval
