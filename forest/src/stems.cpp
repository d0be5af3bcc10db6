#include "treeskel/forest/stems.h"

#include "treeskel/disjoint_sets.h"
#include "treeskel/error.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <unordered_map>

namespace treeskel::forest {

namespace {

constexpr std::size_t kLayerPoints = 8;  // fewest points of a layer for its circle
constexpr double kNoise = 0.01;          // scan noise allowed on top of the relative tolerances
constexpr double kCentreAgreement = 0.5;  // layer circles of one trunk: centres within half a radius ...
constexpr double kRadiusAgreement = 0.4;  // ... and radii within 40%
constexpr double kRingBand = 0.5;
constexpr int kArcBins = 12;             // a ring's coverage counted in twelfths of a turn
constexpr double kInsideShare = 0.1;      // points inside a trunk's ring: at most a tenth of those on it
constexpr int kTrials = 200;              // RANSAC: circles through three points tried per layer
constexpr double kRansacBand = 0.02;      // ... counting the points within 1 cm + 2% of the radius         // a layer's points within half a radius of the reference ring

/// The algebraic circle (Kasa): x² + y² + D x + E y + F = 0 in the least-squares sense.
bool algebraic_circle(const std::vector<Eigen::Vector2d>& pts, Eigen::Vector2d& centre, double& radius) {
  if (pts.size() < 3) return false;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : pts) mean += p;
  mean /= static_cast<double>(pts.size());
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d atb = Eigen::Vector3d::Zero();
  for (const auto& q : pts) {
    const Eigen::Vector2d p = q - mean;  // centred, for conditioning
    const Eigen::Vector3d row(p.x(), p.y(), 1.0);
    ata += row * row.transpose();
    atb += row * -(p.squaredNorm());
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> spectrum(ata, Eigen::EigenvaluesOnly);
  if (!(spectrum.eigenvalues()(0) > 1e-12 * spectrum.eigenvalues()(2))) return false;  // on a line
  const Eigen::Vector3d def = ata.ldlt().solve(atb);
  centre = Eigen::Vector2d(-def(0) / 2, -def(1) / 2);
  const double r2 = centre.squaredNorm() - def(2);
  if (!(r2 > 0) || !std::isfinite(r2)) return false;
  radius = std::sqrt(r2);
  centre += mean;
  return true;
}

/// Gauss-Newton on the geometric distances, from the algebraic circle.
void geometric_circle(const std::vector<Eigen::Vector2d>& pts, Eigen::Vector2d& centre, double& radius) {
  for (int iteration = 0; iteration < 20; ++iteration) {
    Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
    Eigen::Vector3d jtr = Eigen::Vector3d::Zero();
    for (const auto& p : pts) {
      const Eigen::Vector2d d = p - centre;
      const double n = d.norm();
      if (n < 1e-12) continue;
      const Eigen::Vector3d j(-d.x() / n, -d.y() / n, -1.0);
      const double r = n - radius;
      jtj += j * j.transpose();
      jtr += j * r;
    }
    const Eigen::Vector3d step = jtj.ldlt().solve(-jtr);
    if (!step.allFinite()) return;
    centre += step.head<2>();
    radius += step(2);
    if (step.norm() < 1e-9 * std::max(1.0, radius)) return;
  }
}

}  // namespace

Circle fit_circle(const std::vector<Eigen::Vector2d>& points, double min_band) {
  Circle c;
  std::vector<Eigen::Vector2d> kept = points;
  for (int round = 0; round < 3; ++round) {
    Eigen::Vector2d centre;
    double radius = 0;
    if (!algebraic_circle(kept, centre, radius)) return c;
    geometric_circle(kept, centre, radius);
    if (!(radius > 0) || !centre.allFinite()) return c;
    std::vector<double> deviation;
    deviation.reserve(points.size());
    for (const auto& p : points) deviation.push_back(std::abs((p - centre).norm() - radius));
    std::vector<double> sorted = deviation;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double band = std::max(3.0 * sorted[sorted.size() / 2], min_band);
    kept.clear();
    double sum = 0;
    for (std::size_t i = 0; i < points.size(); ++i)
      if (deviation[i] <= band) {
        kept.push_back(points[i]);
        sum += deviation[i] * deviation[i];
      }
    c.centre = centre;
    c.radius = radius;
    c.inliers = kept.size();
    c.rms = kept.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(kept.size()));
    c.ok = kept.size() >= 3;
    if (!c.ok) return c;
  }
  return c;
}

namespace {

/// A trunk's cross section in a scan is a ring: its points cover a quarter turn or more, and hardly
/// any lie inside it (a wide circle through the arcs of a crown's branches holds the trunk inside).
bool trunk_like(const Circle& c, const std::vector<Eigen::Vector2d>& layer) {
  const double band = kNoise + kRansacBand * c.radius;
  std::array<bool, kArcBins> seen{};
  std::size_t inside = 0, on = 0;
  for (const auto& p : layer) {
    const Eigen::Vector2d d = p - c.centre;
    const double r = d.norm();
    if (r < c.radius - 3 * band) ++inside;
    if (std::abs(r - c.radius) > 3 * band) continue;
    ++on;
    const double turn = (std::atan2(d.y(), d.x()) + M_PI) / (2 * M_PI);
    seen[std::min(kArcBins - 1, static_cast<int>(turn * kArcBins))] = true;
  }
  const int bins = static_cast<int>(std::count(seen.begin(), seen.end(), true));
  return bins * 4 >= kArcBins && static_cast<double>(inside) <= kInsideShare * static_cast<double>(on);
}

}  // namespace

Circle find_circle(const std::vector<Eigen::Vector2d>& points, double min_radius, double max_radius, std::uint64_t seed) {
  Circle best;
  if (points.size() < 3) return best;
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> pick(0, points.size() - 1);
  std::ptrdiff_t best_score = 0;
  Eigen::Vector2d best_centre;
  double best_radius = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    const Eigen::Vector2d &a = points[pick(rng)], &b = points[pick(rng)], &c = points[pick(rng)];
    // The circle through a, b, c: its centre is where the perpendicular bisectors meet.
    const Eigen::Vector2d ab = b - a, ac = c - a;
    const double det = 2 * (ab.x() * ac.y() - ab.y() * ac.x());
    if (std::abs(det) < 1e-12) continue;
    const Eigen::Vector2d centre = a + Eigen::Vector2d(ac.y() * ab.squaredNorm() - ab.y() * ac.squaredNorm(),
                                                       ab.x() * ac.squaredNorm() - ac.x() * ab.squaredNorm()) / det;
    const double radius = (a - centre).norm();
    if (radius < min_radius || radius > max_radius) continue;
    // Points on the ring count for it, points inside against it (a trunk's ring is hollow).
    const double band = kNoise + kRansacBand * radius;
    std::ptrdiff_t score = 0;
    for (const auto& p : points) {
      const double d = (p - centre).norm() - radius;
      score += std::abs(d) <= band ? 1 : d < -3 * band ? -2 : 0;
    }
    if (score > best_score) {
      best_score = score;
      best_centre = centre;
      best_radius = radius;
    }
  }
  if (best_score < 3) return best;
  std::vector<Eigen::Vector2d> inliers;
  for (const auto& p : points)
    if (std::abs((p - best_centre).norm() - best_radius) <= kNoise + kRansacBand * best_radius) inliers.push_back(p);
  best = fit_circle(inliers);
  best.ok = best.ok && best.radius >= min_radius && best.radius <= max_radius;
  return best;
}

std::vector<Stem> find_stems(const PointCloud& cloud, const Ground& ground, const StemOptions& o) {
  if (!(o.slice_top > o.slice_bottom) || o.layers < 1 || o.min_layers > o.layers || !(o.gap > 0) ||
      !(o.max_radius > o.min_radius))
    throw OptionError("stems: the slice must have a positive thickness, the layers and the gap must be positive");
  TREESKEL_REQUIRE(ground.height.size() == cloud.size(), "ground of another cloud");
  // The slice's points in plan, with their layer.
  std::vector<Eigen::Vector2d> plan;
  std::vector<int> layer;
  const double thickness = (o.slice_top - o.slice_bottom) / o.layers;
  for (std::size_t p = 0; p < cloud.size(); ++p) {
    const double h = ground.height[p];
    if (ground.is_ground[p] || h < o.slice_bottom || h >= o.slice_top) continue;
    plan.push_back(cloud.positions[p].head<2>());
    layer.push_back(std::min(o.layers - 1, static_cast<int>((h - o.slice_bottom) / thickness)));
  }
  // Groups: points in grid cells of `gap` that touch (8-neighbours) are one group.
  auto key = [&](const Eigen::Vector2d& q) {
    const auto i = static_cast<std::int64_t>(std::floor(q.x() / o.gap));
    const auto j = static_cast<std::int64_t>(std::floor(q.y() / o.gap));
    return (static_cast<std::uint64_t>(i + (1 << 30)) << 32) | static_cast<std::uint64_t>(j + (1 << 30));
  };
  std::unordered_map<std::uint64_t, std::uint32_t> cells;
  std::vector<std::uint32_t> cell_of(plan.size());
  for (std::size_t p = 0; p < plan.size(); ++p)
    cell_of[p] = cells.emplace(key(plan[p]), static_cast<std::uint32_t>(cells.size())).first->second;
  DisjointSets<std::uint32_t> sets(cells.size());
  for (const auto& [k, c] : cells)
    for (int di = -1; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj) {
        const std::uint64_t n = k + (static_cast<std::uint64_t>(static_cast<std::int64_t>(di)) << 32) +
                                static_cast<std::uint64_t>(static_cast<std::int64_t>(dj));
        const auto it = cells.find(n);
        if (it != cells.end()) sets.unite(c, it->second);
      }
  std::unordered_map<std::uint32_t, std::vector<std::size_t>> groups;
  for (std::size_t p = 0; p < plan.size(); ++p) groups[sets.find(cell_of[p])].push_back(p);

  std::vector<Stem> stems;
  for (const auto& [root, members] : groups) {
    if (members.size() < o.min_points) continue;
    // A circle per layer; the layers whose circles agree with the median one are the trunk, so that
    // branches leaving in some layers or a shrub beside it in others do not hide it.
    std::vector<std::vector<Eigen::Vector2d>> per_layer(o.layers);
    for (std::size_t p : members) per_layer[layer[p]].push_back(plan[p]);
    auto is_round = [&](const Circle& c, std::size_t n) {
      return c.ok && c.radius >= o.min_radius && c.radius <= o.max_radius && c.rms <= o.max_rms * c.radius + kNoise &&
             static_cast<double>(c.inliers) >= o.min_inliers * static_cast<double>(n);
    };
    // The circle found in each layer is tried as the reference: every layer is fitted again on its
    // points near the reference's ring (a branch hanging beside the trunk pulls a circle of all the
    // layer's points), and the reference that makes the most layers round wins.
    std::vector<Circle> round;
    for (int ref = 0; ref < o.layers; ++ref) {
      if (per_layer[ref].size() < kLayerPoints) continue;
      const Circle reference = find_circle(per_layer[ref], o.min_radius, o.max_radius, static_cast<std::uint64_t>(ref));
      if (!reference.ok) continue;
      std::vector<Circle> fits;
      for (int l = 0; l < o.layers; ++l) {
        std::vector<Eigen::Vector2d> ring;
        for (const auto& q : per_layer[l])
          if (std::abs((q - reference.centre).norm() - reference.radius) <= kRingBand * reference.radius + kNoise)
            ring.push_back(q);
        if (ring.size() < kLayerPoints) continue;
        const Circle c = fit_circle(ring);
        if (is_round(c, ring.size()) && trunk_like(c, per_layer[l])) fits.push_back(c);
      }
      if (fits.size() > round.size()) round = std::move(fits);
    }
    if (static_cast<int>(round.size()) < o.min_layers) continue;
    auto median = [](std::vector<double> v) {
      std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
      return v[v.size() / 2];
    };
    std::vector<double> xs, ys, rs;
    for (const auto& c : round) {
      xs.push_back(c.centre.x());
      ys.push_back(c.centre.y());
      rs.push_back(c.radius);
    }
    const Eigen::Vector2d centre(median(xs), median(ys));
    const double radius = median(rs);
    std::vector<double> agreeing_r;
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (const auto& c : round)
      if ((c.centre - centre).norm() <= kCentreAgreement * radius + kNoise &&
          std::abs(c.radius - radius) <= kRadiusAgreement * radius + kNoise) {
        agreeing_r.push_back(c.radius);
        sum += c.centre;
      }
    if (static_cast<int>(agreeing_r.size()) < o.min_layers) continue;
    Stem s;
    s.centre = sum / static_cast<double>(agreeing_r.size());
    s.radius = median(agreeing_r);
    s.points = members.size();
    s.ground = ground.terrain.elevation(s.centre.x(), s.centre.y());
    stems.push_back(s);
  }
  // One stem per trunk: of two whose circles overlap (or nearly), the one with more points stays.
  std::sort(stems.begin(), stems.end(), [](const Stem& a, const Stem& b) {
    return a.points != b.points ? a.points > b.points : std::make_pair(a.centre.x(), a.centre.y()) < std::make_pair(b.centre.x(), b.centre.y());
  });
  std::vector<Stem> kept;
  for (const Stem& s : stems) {
    bool apart = true;
    for (const Stem& k : kept) apart = apart && (s.centre - k.centre).norm() > s.radius + k.radius + o.merge;
    if (apart) kept.push_back(s);
  }
  std::sort(kept.begin(), kept.end(), [](const Stem& a, const Stem& b) {
    return std::make_pair(a.centre.x(), a.centre.y()) < std::make_pair(b.centre.x(), b.centre.y());
  });
  return kept;
}

}  // namespace treeskel::forest
