// Stems: circles fitted to rings, arcs and rings among other points, and the stems of a small plot
// with a shrub, a low branch and a ground.
#include "treeskel/error.h"
#include "treeskel/forest/stems.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace treeskel::forest {
namespace {

std::vector<Eigen::Vector2d> ring(const Eigen::Vector2d& c, double r, double from, double to, int n) {
  std::vector<Eigen::Vector2d> pts;
  for (int i = 0; i < n; ++i) {
    const double a = from + (to - from) * i / (n - 1);
    pts.push_back(c + r * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  return pts;
}

TEST(FitCircle, ExactOnARing) {
  const Circle c = fit_circle(ring({1.0, 2.0}, 0.3, 0, 2 * M_PI * 0.95, 40));
  ASSERT_TRUE(c.ok);
  EXPECT_NEAR(c.centre.x(), 1.0, 1e-9);
  EXPECT_NEAR(c.centre.y(), 2.0, 1e-9);
  EXPECT_NEAR(c.radius, 0.3, 1e-9);
  EXPECT_NEAR(c.rms, 0.0, 1e-9);
  EXPECT_EQ(c.inliers, 40u);
}

TEST(FitCircle, AThirdOfANoisyRingSeenFromOneSide) {
  std::mt19937_64 rng(1);
  std::normal_distribution<double> noise(0.0, 0.002);
  auto pts = ring({5.0, -3.0}, 0.2, 0.2, 0.2 + 2 * M_PI / 3, 200);
  for (auto& p : pts) p += Eigen::Vector2d(noise(rng), noise(rng));
  const Circle c = fit_circle(pts);
  ASSERT_TRUE(c.ok);
  EXPECT_NEAR(c.radius, 0.2, 0.01);
  EXPECT_NEAR((c.centre - Eigen::Vector2d(5.0, -3.0)).norm(), 0.0, 0.01);
}

TEST(FitCircle, NoCircleThroughALine) {
  std::vector<Eigen::Vector2d> line;
  for (int i = 0; i < 10; ++i) line.emplace_back(i * 0.1, 0.0);
  EXPECT_FALSE(fit_circle(line).ok);
  EXPECT_FALSE(fit_circle({{0, 0}, {1, 1}}).ok);
}

TEST(FindCircle, FindsATrunkRingBesideABranch) {
  auto pts = ring({0.0, 0.0}, 0.1, 0, 2 * M_PI * 0.98, 120);
  for (int i = 0; i < 100; ++i) pts.emplace_back(0.12 + 0.006 * i, 0.05 + 0.001 * (i % 7));  // a branch leaving
  const Circle all = fit_circle(pts);
  const Circle found = find_circle(pts, 0.02, 1.0, 7);
  ASSERT_TRUE(found.ok);
  EXPECT_NEAR(found.radius, 0.1, 0.003);
  EXPECT_LT(found.centre.norm(), 0.003);
  EXPECT_GE(found.inliers, 115u);
  // The same points with the branch pull a plain fit off the trunk.
  EXPECT_GT(std::abs(all.radius - 0.1) + all.centre.norm(), 0.01);
  EXPECT_EQ(find_circle(pts, 0.02, 1.0, 7).centre, found.centre);  // deterministic
  const Circle wide = find_circle(pts, 0.5, 1.0);  // only circles that wide: never the trunk's
  if (wide.ok) {
    EXPECT_GE(wide.radius, 0.5);
  }
  EXPECT_FALSE(find_circle(pts, 1.5, 2.0).ok);
}

/// A flat ground, three trunks (radii 0.1, 0.2, 0.35) seen from all sides, a shrub, and a branch
/// leaving the first trunk inside the slice.
struct SmallPlot {
  PointCloud cloud;
  std::vector<Eigen::Vector2d> centres{{2.0, 2.0}, {6.0, 3.0}, {4.0, 7.0}};
  std::vector<double> radii{0.1, 0.2, 0.35};
  SmallPlot() {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::normal_distribution<double> noise(0.0, 0.003);
    for (int i = 0; i < 20000; ++i) cloud.positions.emplace_back(10 * u(rng), 10 * u(rng), noise(rng));
    for (std::size_t t = 0; t < centres.size(); ++t)
      for (int i = 0; i < 6000; ++i) {
        const double a = 2 * M_PI * u(rng), r = radii[t] + noise(rng);
        cloud.positions.emplace_back(centres[t].x() + r * std::cos(a), centres[t].y() + r * std::sin(a), 4.0 * u(rng));
      }
    for (int i = 0; i < 3000; ++i) {  // a shrub of scattered points at (8, 8)
      Eigen::Vector3d d(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
      cloud.positions.push_back(Eigen::Vector3d(8, 8, 0.7) + 1.2 * d);
    }
    for (int i = 0; i < 800; ++i) {  // a branch leaving the first trunk at 1.1 m
      const double s = 1.5 * u(rng);
      cloud.positions.emplace_back(2.1 + s, 2.0 + 0.03 * noise(rng), 1.1 + 0.5 * s + noise(rng));
    }
  }
};

TEST(FindStems, FindsEachTrunkOnceAndNotTheShrub) {
  const SmallPlot plot;
  const Ground ground = classify_ground(plot.cloud);
  const std::vector<Stem> stems = find_stems(plot.cloud, ground);
  ASSERT_EQ(stems.size(), 3u);
  // In order of x: (2, 2), (4, 7), (6, 3).
  const int order[3] = {0, 2, 1};
  for (int i = 0; i < 3; ++i) {
    const int t = order[i];
    EXPECT_NEAR((stems[i].centre + plot.cloud.offset.head<2>() - plot.centres[t]).norm(), 0.0, 0.01) << t;
    EXPECT_NEAR(stems[i].radius, plot.radii[t], 0.01) << t;
    EXPECT_NEAR(stems[i].ground + plot.cloud.offset.z(), 0.0, 0.05);
  }
}

TEST(FindStems, RefusesASliceUpsideDown) {
  const SmallPlot plot;
  const Ground ground = classify_ground(plot.cloud);
  StemOptions o;
  o.slice_bottom = 2.0;
  o.slice_top = 1.0;
  EXPECT_THROW(find_stems(plot.cloud, ground, o), OptionError);
}

}  // namespace
}  // namespace treeskel::forest
