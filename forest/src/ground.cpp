#include "treeskel/forest/ground.h"
#include "treeskel/forest/stems.h"

#include "treeskel/error.h"

#include <Eigen/Dense>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

namespace treeskel::forest {

namespace {

constexpr double kEmpty = std::numeric_limits<double>::infinity();
constexpr double kPlaneRadius = 3.0;  // metres of ground around a cell that give its local plane

/// Grey-scale erosion (min) or dilation (max) of the grid with a square window of half-width `r`
/// cells, separable: along x, then along y.
std::vector<double> morph(const std::vector<double>& in, int nx, int ny, int r, bool erode) {
  auto pick = [erode](double a, double b) { return erode ? std::min(a, b) : std::max(a, b); };
  std::vector<double> rows(in.size()), out(in.size());
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      double v = in[j * nx + i];
      for (int k = std::max(0, i - r); k <= std::min(nx - 1, i + r); ++k) v = pick(v, in[j * nx + k]);
      rows[j * nx + i] = v;
    }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      double v = rows[j * nx + i];
      for (int k = std::max(0, j - r); k <= std::min(ny - 1, j + r); ++k) v = pick(v, rows[k * nx + i]);
      out[j * nx + i] = v;
    }
  return out;
}

/// The plane z = a + b x + c y (cell units) through the ground cells near cell (i, j), least squares:
/// those within `radius` cells, the radius doubled until six are found. False when there are fewer
/// than three ground cells in all, or they lie on a line.
bool local_plane(const std::vector<double>& lowest, const std::vector<bool>& ground, int nx, int ny, int i, int j,
                 int radius, double& z) {
  for (int r = radius;; r *= 2) {
    Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
    Eigen::Vector3d atb = Eigen::Vector3d::Zero();
    int n = 0;
    for (int v = std::max(0, j - r); v <= std::min(ny - 1, j + r); ++v)
      for (int u = std::max(0, i - r); u <= std::min(nx - 1, i + r); ++u) {
        if (!ground[v * nx + u] || (u - i) * (u - i) + (v - j) * (v - j) > r * r) continue;
        const Eigen::Vector3d row(1.0, u - i, v - j);
        ata += row * row.transpose();
        atb += row * lowest[v * nx + u];
        ++n;
      }
    const bool whole_grid = r >= nx + ny;
    if (n >= 6 || (whole_grid && n >= 3)) {
      const Eigen::Vector3d abc = ata.ldlt().solve(atb);
      if (!abc.allFinite() || std::abs(ata.determinant()) < 1e-9) return false;
      z = abc(0);
      return true;
    }
    if (whole_grid) return false;
  }
}

/// Fills the empty cells of the grid with the value of the nearest filled cell (breadth first, so
/// the 4-connected nearest), and returns false when no cell is filled.
bool fill_empty(std::vector<double>& z, int nx, int ny) {
  std::deque<int> queue;
  for (int c = 0; c < nx * ny; ++c)
    if (z[c] != kEmpty) queue.push_back(c);
  if (queue.empty()) return false;
  while (!queue.empty()) {
    const int c = queue.front();
    queue.pop_front();
    const int i = c % nx, j = c / nx;
    const int next[4][2] = {{i - 1, j}, {i + 1, j}, {i, j - 1}, {i, j + 1}};
    for (const auto& n : next) {
      if (n[0] < 0 || n[1] < 0 || n[0] >= nx || n[1] >= ny) continue;
      const int d = n[1] * nx + n[0];
      if (z[d] != kEmpty) continue;
      z[d] = z[c];
      queue.push_back(d);
    }
  }
  return true;
}

}  // namespace

double Terrain::elevation(double x, double y) const {
  TREESKEL_REQUIRE(nx > 0 && ny > 0, "empty terrain");
  const double fx = std::clamp((x - origin.x()) / cell - 0.5, 0.0, static_cast<double>(nx - 1));
  const double fy = std::clamp((y - origin.y()) / cell - 0.5, 0.0, static_cast<double>(ny - 1));
  const int i = std::min(static_cast<int>(fx), nx - 1), j = std::min(static_cast<int>(fy), ny - 1);
  const int i1 = std::min(i + 1, nx - 1), j1 = std::min(j + 1, ny - 1);
  const double u = fx - i, v = fy - j;
  const double bottom = (1 - u) * z[j * nx + i] + u * z[j * nx + i1];
  const double top = (1 - u) * z[j1 * nx + i] + u * z[j1 * nx + i1];
  return (1 - v) * bottom + v * top;
}

Ground classify_ground(const PointCloud& cloud, const GroundOptions& options, const std::vector<std::uint8_t>* classes) {
  if (cloud.empty()) throw InputError("the cloud has no points");
  if (!(options.cell > 0) || !(options.max_window >= 0) || !(options.slope >= 0) || !(options.tolerance >= 0))
    throw OptionError("ground: the cell must be positive, the window, slope and tolerance not negative");
  TREESKEL_REQUIRE(!classes || classes->size() == cloud.size(), "one class per point");
  constexpr std::uint8_t kLasGround = 2;
  const bool classified =
      classes && std::find(classes->begin(), classes->end(), kLasGround) != classes->end();

  const Eigen::AlignedBox3d box = bounding_box(cloud);
  Ground g;
  Terrain& t = g.terrain;
  t.cell = options.cell;
  t.origin = box.min().head<2>();
  const double span_x = box.sizes().x(), span_y = box.sizes().y();
  if (span_x / t.cell > 1e5 || span_y / t.cell > 1e5)
    throw InputError("the plot is " + std::to_string(span_x) + " by " + std::to_string(span_y) +
                     " units wide: too wide for a ground grid of " + std::to_string(t.cell) +
                     " (is it in metres?)");
  t.nx = std::max(1, static_cast<int>(std::floor(span_x / t.cell)) + 1);
  t.ny = std::max(1, static_cast<int>(std::floor(span_y / t.cell)) + 1);
  auto cell_of = [&](const Eigen::Vector3d& p) {
    const int i = std::clamp(static_cast<int>((p.x() - t.origin.x()) / t.cell), 0, t.nx - 1);
    const int j = std::clamp(static_cast<int>((p.y() - t.origin.y()) / t.cell), 0, t.ny - 1);
    return j * t.nx + i;
  };

  // The lowest point of each cell (of the classified ground, when there is one).
  std::vector<double> lowest(static_cast<std::size_t>(t.nx) * t.ny, kEmpty);
  for (std::size_t p = 0; p < cloud.size(); ++p) {
    if (classified && (*classes)[p] != kLasGround) continue;
    double& z = lowest[cell_of(cloud.positions[p])];
    z = std::min(z, cloud.positions[p].z());
  }
  // A cell with no point is never ground: the terrain there comes from its nearest ground cell (else a
  // gap between trees, filled from the crowns around it, could pass for a plateau of ground).
  std::vector<bool> ground_cell(lowest.size(), true);  // written by one thread
  for (std::size_t c = 0; c < lowest.size(); ++c) ground_cell[c] = lowest[c] != kEmpty;
  const std::vector<bool> has_points = ground_cell;
  fill_empty(lowest, t.nx, t.ny);

  std::vector<double> surface = lowest;
  if (!classified) {
    // Opening with growing windows; a cell that stands above the opened surface by more than the
    // window's threshold is not ground (Zhang et al. 2003, with windows 2^k + 1 cells wide).
    int previous = 1;
    for (int w = 3; (w - 2) * t.cell <= options.max_window; w = 2 * w - 1) {
      const int r = w / 2;
      const std::vector<double> opened = morph(morph(surface, t.nx, t.ny, r, true), t.nx, t.ny, r, false);
      const double threshold =
          std::min(options.max_threshold, options.initial_threshold + options.slope * (w - previous) * t.cell);
      for (std::size_t c = 0; c < surface.size(); ++c)
        if (surface[c] - opened[c] > threshold) ground_cell[c] = false;
      surface = opened;
      previous = w;
    }
  }
  // The terrain: the lowest points of the ground cells; elsewhere the plane of the ground cells around.
  // A cell the filter lifted off whose lowest point lies on that plane is ground after all: the
  // opening, its windows cut short at the grid's edge, lowers a sloping terrain there.
  const int radius = std::max(2, static_cast<int>(std::lround(kPlaneRadius / t.cell)));
  std::vector<double> plane(lowest.size(), kEmpty);
  if (!classified)
    for (int j = 0; j < t.ny; ++j)
      for (int i = 0; i < t.nx; ++i) {
        const std::size_t c = static_cast<std::size_t>(j) * t.nx + i;
        if (ground_cell[c] || !has_points[c]) continue;
        double z = 0;
        if (local_plane(lowest, ground_cell, t.nx, t.ny, i, j, radius, z)) plane[c] = z;
      }
  for (std::size_t c = 0; c < lowest.size(); ++c)
    if (plane[c] != kEmpty && std::abs(lowest[c] - plane[c]) <= options.initial_threshold) ground_cell[c] = true;
  t.z.assign(lowest.size(), kEmpty);
  for (std::size_t c = 0; c < lowest.size(); ++c)
    if (ground_cell[c]) t.z[c] = lowest[c];
  for (int j = 0; j < t.ny; ++j)
    for (int i = 0; i < t.nx; ++i) {
      const std::size_t c = static_cast<std::size_t>(j) * t.nx + i;
      double z = 0;
      if (!ground_cell[c] && local_plane(lowest, ground_cell, t.nx, t.ny, i, j, radius, z)) plane[c] = z;
      else plane[c] = kEmpty;
    }
  for (std::size_t c = 0; c < lowest.size(); ++c)
    if (!ground_cell[c] && plane[c] != kEmpty) t.z[c] = plane[c];
  if (!fill_empty(t.z, t.nx, t.ny)) t.z = surface;

  g.is_ground.resize(cloud.size());
  g.height.resize(cloud.size());
  tbb::parallel_for(std::size_t{0}, cloud.size(), [&](std::size_t p) {
    const Eigen::Vector3d& q = cloud.positions[p];
    const double h = q.z() - t.elevation(q.x(), q.y());
    g.height[p] = static_cast<float>(h);
    g.is_ground[p] = classified ? (*classes)[p] == kLasGround : h <= options.tolerance;
  });
  g.ground_points = static_cast<std::size_t>(std::count(g.is_ground.begin(), g.is_ground.end(), std::uint8_t{1}));
  return g;
}

GroundUnderTree ground_under_tree(const PointCloud& cloud, const Eigen::Vector3d& up) {
  GroundUnderTree out;
  if (cloud.size() == 0 || up.norm() == 0.0) return out;
  // The cloud turned so that `up` is z (its plan axes any two orthogonal to it).
  const Eigen::Vector3d z = up.normalized();
  const Eigen::Vector3d x = z.unitOrthogonal(), y = z.cross(x);
  PointCloud turned;
  turned.positions.reserve(cloud.size());
  double low = kEmpty, high = -kEmpty;
  for (const auto& p : cloud.positions) {
    turned.positions.emplace_back(p.dot(x), p.dot(y), p.dot(z));
    low = std::min(low, turned.positions.back().z());
    high = std::max(high, turned.positions.back().z());
  }
  if (!(high - low >= 1.0 && high - low <= 200.0)) return out;
  const GroundOptions options;
  Ground g = classify_ground(turned, options, cloud.classes.size() == cloud.size() ? &cloud.classes : nullptr);
  if (g.ground_points == 0) return out;
  // The stem: the largest that find_stems sees in the slice above this ground. With none, the
  // "ground" cannot be told from the foot of whatever stands on it, and nothing is set aside.
  const std::vector<Stem> stems = find_stems(turned, g);
  if (stems.empty()) return out;
  const Stem& stem = *std::max_element(stems.begin(), stems.end(), [](const Stem& p, const Stem& q) {
    return p.radius < q.radius;
  });
  const Eigen::Vector2d foot = stem.centre;
  out.stem_radius = stem.radius;
  const double beyond = std::max(3.0 * out.stem_radius, out.stem_radius + 0.3);
  for (std::size_t i = 0; i < turned.size(); ++i)
    if (g.is_ground[i] && (turned.positions[i].head<2>() - foot).norm() > beyond) ++out.beyond_stem;
  if (out.beyond_stem < std::max(kGroundBeyondStem, cloud.size() / 1000)) return out;
  // Set aside: the ground outside the stem (within it, the lowest points are the stem's own foot
  // and stay, so the tree keeps its height and its breast height), and whatever lies on the ground
  // below the slice stems are found in outside a skirt around the stem (litter, low plants, the
  // ground's own noise; left, it would be the trunk's foot).
  const double bark = out.stem_radius + std::max(0.02, 0.1 * out.stem_radius);
  const double skirt = 1.5 * out.stem_radius + 0.05;
  const double low_slice = StemOptions{}.slice_bottom;
  out.is_ground.assign(turned.size(), 0);
  for (std::size_t i = 0; i < turned.size(); ++i) {
    const double from_stem = (turned.positions[i].head<2>() - foot).norm();
    if ((g.is_ground[i] && from_stem > bark) || (g.height[i] < low_slice && from_stem > skirt)) {
      out.is_ground[i] = 1;
      ++out.ground_points;
    }
  }
  return out;
}

}  // namespace treeskel::forest
