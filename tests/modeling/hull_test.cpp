// The joins' convex hull (modeling/src/hull.h, private to the library), alone.
#include "../../modeling/src/hull.h"

#include <gtest/gtest.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <utility>
#include <vector>

namespace treeskel::modeling::detail {
namespace {

using Eigen::Vector3d;
using Faces = std::vector<std::array<std::size_t, 3>>;

// Every directed edge once and its reverse once: a closed surface, consistently oriented.
void expect_closed(const Faces& faces) {
  std::map<std::pair<std::size_t, std::size_t>, int> edges;
  for (const auto& f : faces)
    for (int k = 0; k < 3; ++k) ++edges[{f[k], f[(k + 1) % 3]}];
  for (const auto& [e, count] : edges) {
    EXPECT_EQ(count, 1) << e.first << "-" << e.second;
    EXPECT_EQ(edges.count({e.second, e.first}), 1u) << e.first << "-" << e.second;
  }
}

double volume(const std::vector<Vector3d>& p, const Faces& faces) {
  double v = 0.0;
  for (const auto& f : faces) v += p[f[0]].dot(p[f[1]].cross(p[f[2]])) / 6.0;
  return v;
}

double area(const std::vector<Vector3d>& p, const std::array<std::size_t, 3>& f) {
  return 0.5 * (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]).norm();
}

// A cube's faces hold four points each: CGAL's diagonal depends on its memory; ours is the one
// from the face's lowest index, in whatever order the corners come.
TEST(Hull, EachFlatFaceIsFannedFromItsLowestIndex) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 12; ++trial) {
    std::vector<Vector3d> p;
    for (int c = 0; c < 8; ++c) p.emplace_back(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    std::shuffle(p.begin(), p.end(), rng);
    const Faces faces = convex_hull_faces(p);
    ASSERT_EQ(faces.size(), 12u);
    expect_closed(faces);
    EXPECT_NEAR(volume(p, faces), 1.0, 1e-12);
    for (int axis = 0; axis < 3; ++axis)
      for (double side : {0.0, 1.0}) {
        std::size_t lowest = p.size();
        for (std::size_t i = 0; i < p.size(); ++i)
          if (p[i][axis] == side) lowest = std::min(lowest, i);
        int on_face = 0;
        for (const auto& f : faces)
          if (p[f[0]][axis] == side && p[f[1]][axis] == side && p[f[2]][axis] == side) {
            ++on_face;
            EXPECT_TRUE(std::find(f.begin(), f.end(), lowest) != f.end()) << "trial " << trial << " axis " << axis << " side " << side;
          }
        EXPECT_EQ(on_face, 2);
      }
  }
}

// Two rings (groups) that share a face of the hull: each keeps its own polygon there (the sweep
// leaves those triangles out, the ring's opening), and the rest of the face joins them.
TEST(Hull, AGroupInAFlatFaceKeepsItsOwnPolygon) {
  std::vector<Vector3d> p;
  std::vector<std::size_t> group;
  const double pi = std::acos(-1.0);
  for (int k = 0; k < 8; ++k) {  // an octagon: A is its first four corners, B the last four
    p.emplace_back(std::cos(2 * pi * k / 8), std::sin(2 * pi * k / 8), 0.0);
    group.push_back(k < 4 ? 0 : 1);
  }
  p.emplace_back(0.1, 0.2, 1.0);  // an apex above
  group.push_back(2);
  const Faces faces = convex_hull_faces(p, group);
  expect_closed(faces);
  EXPECT_GT(volume(p, faces), 0.0);
  // A's and B's quads: (0 1 2 3) and (4 5 6 7), each half the octagon less a triangle.
  auto quad_area = [&](std::size_t a) { return area(p, {a, a + 1, a + 2}) + area(p, {a, a + 2, a + 3}); };
  std::map<std::size_t, double> own;
  for (const auto& f : faces)
    if (group[f[0]] == group[f[1]] && group[f[1]] == group[f[2]]) own[group[f[0]]] += area(p, f);
  ASSERT_EQ(own.size(), 2u);
  EXPECT_NEAR(own[0], quad_area(0), 1e-12);
  EXPECT_NEAR(own[1], quad_area(4), 1e-12);
  // Without the groups the fan from 0 crosses B's quad: B's polygon is not kept.
  double b_alone = 0.0;
  for (const auto& f : convex_hull_faces(p))
    if (group[f[0]] == 1 && group[f[1]] == 1 && group[f[2]] == 1) b_alone += area(p, f);
  EXPECT_LT(b_alone, quad_area(4) - 1e-3);
}

// A point on a side of the hull, in line with two corners, is no corner (so no fan can degenerate;
// the sweep takes a ring's point that is no corner to mean the rings do not fit).
TEST(Hull, APointOnASideIsNoCorner) {
  // A square pyramid on a base whose side from 0 to 1 holds point 4 at its middle.
  const std::vector<Vector3d> p{{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {1, 0, 0}, {1, 1, 3}};
  const Faces faces = convex_hull_faces(p);
  expect_closed(faces);
  EXPECT_EQ(faces.size(), 6u);
  for (const auto& f : faces) EXPECT_TRUE(std::find(f.begin(), f.end(), 4u) == f.end());
  EXPECT_NEAR(volume(p, faces), 4.0, 1e-12);
}

TEST(Hull, WithoutFlatFacesEveryPointIsACorner) {
  std::mt19937 rng(3);
  std::normal_distribution<double> gauss;
  std::vector<Vector3d> p;
  for (int i = 0; i < 40; ++i) p.push_back(Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized());
  const Faces faces = convex_hull_faces(p);
  expect_closed(faces);
  EXPECT_EQ(faces.size(), 2 * p.size() - 4);
  EXPECT_GT(volume(p, faces), 0.0);
}

// Joins' rings: flat polygons in doubles, tilted, so four of a ring's points are coplanar up to
// rounding and the hull's tests meet near-ties at almost every step (the hull settles them in its
// own exact arithmetic, not CGAL's default). Every face has all points on or behind it, exactly,
// and the corners are those of the hull CGAL's default traits give.
TEST(Hull, FlatRingsGiveTheCornersOfCgalsOwnHull) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const double pi = std::acos(-1.0);
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<Vector3d> p;
    std::vector<std::size_t> group;
    const int rings = 2 + trial % 3;
    for (int r = 0; r < rings; ++r) {
      const Vector3d centre(unit(rng), unit(rng), unit(rng) + 2.0 * r);
      const Vector3d axis = Vector3d(unit(rng), unit(rng), 2.0).normalized();
      const Vector3d u = axis.unitOrthogonal(), v = axis.cross(u);
      const int sides = 6 + 6 * (trial % 3);
      const double radius = 0.2 + 0.3 * std::abs(unit(rng));
      for (int k = 0; k < sides; ++k) {
        const double a = 2 * pi * k / sides;
        p.push_back(centre + radius * (std::cos(a) * u + std::sin(a) * v));
        group.push_back(static_cast<std::size_t>(r));
      }
    }
    const Faces faces = convex_hull_faces(p, group);
    expect_closed(faces);
    std::vector<K::Point_3> q;
    for (const auto& x : p) q.emplace_back(x.x(), x.y(), x.z());
    std::set<std::size_t> corners;
    for (const auto& f : faces) {
      corners.insert(f.begin(), f.end());
      for (const auto& x : q) EXPECT_NE(CGAL::orientation(q[f[0]], q[f[1]], q[f[2]], x), CGAL::POSITIVE) << "trial " << trial;
    }
    CGAL::Surface_mesh<K::Point_3> theirs;
    CGAL::convex_hull_3(q.begin(), q.end(), theirs);
    std::set<std::size_t> their_corners;
    for (auto v : theirs.vertices())
      for (std::size_t i = 0; i < q.size(); ++i)
        if (q[i] == theirs.point(v)) their_corners.insert(i);
    EXPECT_EQ(corners, their_corners) << "trial " << trial;
  }
}

TEST(Hull, APointGivenTwiceStandsForItselfByItsLastIndex) {
  const std::vector<Vector3d> p{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 0}};
  const Faces faces = convex_hull_faces(p);
  ASSERT_EQ(faces.size(), 4u);
  std::set<std::size_t> used;
  for (const auto& f : faces) used.insert(f.begin(), f.end());
  EXPECT_EQ(used, (std::set<std::size_t>{0, 2, 3, 4}));
  EXPECT_THROW(convex_hull_faces(p, {0, 1}), std::invalid_argument);
}

}  // namespace
}  // namespace treeskel::modeling::detail
