#include "treeskel/l1_median.h"

#include <gtest/gtest.h>

#include <random>

namespace treeskel {
namespace {

TEST(L1Median, SymmetricSetGivesItsCentre) {
  const std::vector<Eigen::Vector3d> pts{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  EXPECT_LT(l1_median(pts).norm(), 1e-9);
}

const L1MedianOptions precise{500, 1e-12, 4096};

TEST(L1Median, ObtuseTriangleGivesTheObtuseVertex) {
  // The angle at (0,0,0) is 150 degrees > 120: the Fermat point is that vertex (Vardi-Zhang step).
  const std::vector<Eigen::Vector3d> pts{{0, 0, 0}, {1, 0, 0}, {-std::cos(M_PI / 6), std::sin(M_PI / 6), 0}};
  EXPECT_LT(l1_median(pts, precise).norm(), 1e-9);
}

TEST(L1Median, EquilateralTriangleGivesTheFermatPoint) {
  const std::vector<Eigen::Vector3d> pts{{1, 0, 0}, {-0.5, std::sqrt(3.0) / 2, 0}, {-0.5, -std::sqrt(3.0) / 2, 0}};
  EXPECT_LT(l1_median(pts, precise).norm(), 1e-9);
}

TEST(L1Median, ResistsOutliersUnlikeTheMean) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 0.01);
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 200; ++i) pts.emplace_back(g(rng), g(rng), g(rng));
  for (int i = 0; i < 20; ++i) pts.emplace_back(10.0, 0.0, 0.0);
  EXPECT_LT(l1_median(pts).norm(), 0.01);
}

TEST(L1Median, ThinsLargeSetsEvenly) {
  // 100,000 points on a circle: thinned to about 4096, the median is still the centre.
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 100000; ++i) pts.emplace_back(std::cos(i * 2e-5 * M_PI), std::sin(i * 2e-5 * M_PI), 0.0);
  EXPECT_LT(l1_median(pts).norm(), 1e-3);
}

TEST(L1Median, UsesOnlyTheIndexedPoints) {
  const std::vector<Eigen::Vector3d> pts{{100, 0, 0}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
  const std::uint32_t idx[] = {1, 2, 3};
  EXPECT_LT((l1_median(pts, idx, idx + 3) - Eigen::Vector3d(1, 1, 1)).norm(), 1e-12);
  EXPECT_EQ(l1_median(pts, idx, idx), Eigen::Vector3d::Zero());
}

}  // namespace
}  // namespace treeskel
