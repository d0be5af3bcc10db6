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

// The Weiszfeld step written the plain way, one point at a time (with Vardi & Zhang's rule at a data
// point): the library's step, which does two points at a time where the CPU can, must give its bits.
Eigen::Vector3d plain_weiszfeld(const std::vector<Eigen::Vector3d>& p, const L1MedianOptions& o) {
  const std::size_t n = p.size();
  Eigen::Vector3d y = Eigen::Vector3d::Zero(), lo = p[0], hi = p[0];
  for (const auto& q : p) {
    y += q;
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  y /= static_cast<double>(n);
  const double extent = (hi - lo).norm();
  if (n <= 2 || extent == 0.0) return y;
  for (int it = 0; it < o.max_iterations; ++it) {
    Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
    double weight_sum = 0.0;
    int coincident = 0;
    for (const auto& q : p) {
      const double d = (q - y).norm();
      if (d <= 1e-12 * extent) {
        ++coincident;
        continue;
      }
      weighted += q / d;
      weight_sum += 1.0 / d;
    }
    if (weight_sum == 0.0) break;
    const Eigen::Vector3d t = weighted / weight_sum;
    Eigen::Vector3d next = t;
    if (coincident > 0) {
      const double r = ((t - y) * weight_sum).norm();
      if (r <= coincident) break;
      next = (1.0 - coincident / r) * t + (coincident / r) * y;
    }
    const double step = (next - y).norm();
    y = next;
    if (step < o.tolerance * extent) break;
  }
  return y;
}

TEST(L1Median, GivesThePlainStepsBits) {
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0.0, 1.0);
  for (std::size_t n = 1; n <= 41; ++n) {
    std::vector<Eigen::Vector3d> p;
    for (std::size_t i = 0; i < n; ++i) p.emplace_back(3.0 + g(rng), -2.0 + 0.1 * g(rng), 40.0 + 5.0 * g(rng));
    if (n > 6) p[n / 2] = p[1];  // a repeated point
    const Eigen::Vector3d expected = plain_weiszfeld(p, {});
    const Eigen::Vector3d got = l1_median(p);
    for (int a = 0; a < 3; ++a) EXPECT_EQ(got[a], expected[a]) << n << " points, axis " << a;
  }
  // The median of five points, one of them the median: the step stops at a data point.
  const std::vector<Eigen::Vector3d> star{{0, 0, 0}, {1, 0, 0}, {-1, 0.1, 0}, {0, 1, 0.2}, {0.1, -1, 0}};
  EXPECT_EQ(l1_median(star), plain_weiszfeld(star, {}));
}

}  // namespace
}  // namespace treeskel
