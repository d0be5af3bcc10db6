#include "treeskel/eval/plots.h"

#include "treeskel/error.h"
#include "treeskel/eval/cylinders.h"
#include "treeskel/eval/tree_generator.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>

namespace treeskel::eval {

namespace {

double ground_elevation(const PlotOptions& o, double x, double y) {
  return o.slope * x + o.roughness * (std::sin(1.3 * x + 0.4) * std::cos(0.9 * y) + 0.5 * std::sin(2.7 * y + 1.1 * x));
}

void add(SyntheticPlot& plot, const Eigen::Vector3d& p, std::uint32_t tree, PointKind kind) {
  plot.cloud.positions.push_back(p);
  plot.tree.push_back(tree);
  plot.kind.push_back(kind);
}

}  // namespace

SyntheticPlot make_plot(const PlotOptions& o) {
  if (o.trees < 1 || !(o.width > 0) || o.scanners < 1) throw OptionError("a plot needs trees, a width and a scanner");
  std::mt19937_64 rng(o.seed);
  auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
  std::normal_distribution<double> gauss(0.0, 1.0);
  SyntheticPlot plot;

  // Stems: random places at least min_spacing apart, a margin from the edge.
  const double margin = 0.15 * o.width;
  for (int attempt = 0; static_cast<int>(plot.stems.size()) < o.trees && attempt < 10000; ++attempt) {
    const double x = uniform(margin, o.width - margin), y = uniform(margin, o.width - margin);
    bool apart = true;
    for (const auto& s : plot.stems) apart = apart && std::hypot(s.x() - x, s.y() - y) >= o.min_spacing;
    if (apart) plot.stems.emplace_back(x, y, ground_elevation(o, x, y));
  }
  std::vector<Eigen::Vector3d> scanners;
  for (int s = 0; s < o.scanners; ++s) {
    const double a = 2 * M_PI * (s + 0.25) / o.scanners;
    const double x = o.width / 2 + 0.6 * o.width * std::cos(a), y = o.width / 2 + 0.6 * o.width * std::sin(a);
    scanners.emplace_back(x, y, ground_elevation(o, x, y) + 1.5);
  }

  for (std::size_t t = 0; t < plot.stems.size(); ++t) {
    GrowOptions g;
    g.seed = o.seed * 1000 + t + 1;
    g.height = uniform(9.0, 15.0);
    g.trunk_radius = uniform(0.1, 0.22);
    g.branches = static_cast<int>(uniform(6, 10));
    g.orders = 3;
    g.length_ratio = 0.45;  // crowns a few metres wide, as in a stand
    g.bend = 0.03;          // trunks that stand up
    GrownTree grown = grow_tree(g);
    // Sink the base a little into the ground, so the trunk meets it on a slope.
    const Eigen::Vector3d base = plot.stems[t] - Eigen::Vector3d(0, 0, 0.3);
    for (auto& c : grown.cylinders) {
      c.a += base;
      c.b += base;
    }
    for (std::size_t s = 0; s < scanners.size(); ++s) {
      SurfaceSampling sampling;
      sampling.points = o.points_per_tree / scanners.size();
      sampling.seed = g.seed * 100 + s;
      sampling.noise = o.noise;
      Eigen::Vector3d toward = scanners[s] - plot.stems[t];
      toward.z() = 0;
      sampling.facing = toward.normalized();
      const PointCloud part = sample_cylinders(grown.cylinders, sampling);
      for (const auto& p : part.positions)
        if (p.z() > ground_elevation(o, p.x(), p.y())) add(plot, p + part.offset, static_cast<std::uint32_t>(t + 1), PointKind::wood);
    }
    if (!o.leaves) continue;
    // Leaves: a cluster of small scattered points at every tip (a cylinder no other grows from).
    std::vector<bool> has_child(grown.cylinders.size(), false);
    for (int parent : grown.parent)
      if (parent >= 0) has_child[parent] = true;
    const std::size_t tips = static_cast<std::size_t>(std::count(has_child.begin(), has_child.end(), false));
    const std::size_t per_tip = std::max<std::size_t>(8, o.points_per_tree / 2 / std::max<std::size_t>(tips, 1));
    for (std::size_t c = 0; c < grown.cylinders.size(); ++c) {
      if (has_child[c]) continue;
      const Eigen::Vector3d tip = grown.cylinders[c].b;
      for (std::size_t k = 0; k < per_tip; ++k) {
        const Eigen::Vector3d d(gauss(rng), gauss(rng), gauss(rng));
        add(plot, tip + 0.08 * d, static_cast<std::uint32_t>(t + 1), PointKind::leaf);
      }
    }
  }

  // Understorey: shrubs, ellipsoids of scattered points up to 1.2 m high, not on a stem.
  for (int s = 0, attempt = 0; s < o.shrubs && attempt < 1000; ++attempt) {
    const double x = uniform(0.5, o.width - 0.5), y = uniform(0.5, o.width - 0.5);
    bool apart = true;
    for (const auto& st : plot.stems) apart = apart && std::hypot(st.x() - x, st.y() - y) > 0.8;
    if (!apart) continue;
    ++s;
    const double rx = uniform(0.3, 0.6), ry = uniform(0.3, 0.6), rz = uniform(0.3, 0.6);
    const double z0 = ground_elevation(o, x, y) + rz;
    for (int k = 0; k < 600; ++k) {
      Eigen::Vector3d d(gauss(rng), gauss(rng), gauss(rng));
      d = d.normalized() * std::cbrt(uniform(0.0, 1.0));
      add(plot, {x + rx * d.x(), y + ry * d.y(), z0 + rz * d.z()}, 0, PointKind::understorey);
    }
  }

  // The ground: random points on the rough surface, with noise.
  const auto ground_points = static_cast<std::size_t>(o.ground_density * o.width * o.width);
  for (std::size_t k = 0; k < ground_points; ++k) {
    const double x = uniform(0, o.width), y = uniform(0, o.width);
    add(plot, {x, y, ground_elevation(o, x, y) + o.noise * gauss(rng)}, 0, PointKind::ground);
  }
  recentre_offset(plot.cloud);
  for (auto& s : plot.stems) s -= plot.cloud.offset;
  return plot;
}

PlotScore score_plot(const SyntheticPlot& plot, const std::vector<Eigen::Vector2d>& found,
                     const std::vector<std::uint32_t>& labels, double match_distance) {
  TREESKEL_REQUIRE(labels.size() == plot.cloud.size(), "a label per point");
  PlotScore s;
  s.true_stems = plot.stems.size();
  s.found_stems = found.size();
  std::vector<std::tuple<double, std::size_t, std::size_t>> pairs;
  for (std::size_t t = 0; t < plot.stems.size(); ++t)
    for (std::size_t f = 0; f < found.size(); ++f) {
      const double d = (plot.stems[t].head<2>() - found[f]).norm();
      if (d <= match_distance) pairs.emplace_back(d, t, f);
    }
  std::sort(pairs.begin(), pairs.end());
  std::vector<long> match_of_true(plot.stems.size(), -1);
  std::vector<bool> found_used(found.size(), false);
  for (const auto& [d, t, f] : pairs) {
    if (match_of_true[t] >= 0 || found_used[f]) continue;
    match_of_true[t] = static_cast<long>(f);
    found_used[f] = true;
    ++s.matched_stems;
  }
  s.stem_precision = found.empty() ? 0.0 : static_cast<double>(s.matched_stems) / static_cast<double>(found.size());
  s.stem_recall = plot.stems.empty() ? 0.0 : static_cast<double>(s.matched_stems) / static_cast<double>(plot.stems.size());
  // IoU per true tree with its matched found tree.
  std::vector<std::size_t> both(plot.stems.size(), 0), in_true(plot.stems.size(), 0), in_found(found.size() + 1, 0);
  std::size_t elsewhere = 0, unassigned = 0, tree_points = 0, others = 0, others_in = 0;
  for (std::size_t p = 0; p < labels.size(); ++p) {
    if (labels[p] > 0 && labels[p] <= found.size()) ++in_found[labels[p]];
    const std::uint32_t t = plot.tree[p];
    if (t == 0) {
      ++others;
      others_in += labels[p] != 0;
      continue;
    }
    ++tree_points;
    ++in_true[t - 1];
    if (match_of_true[t - 1] >= 0 && labels[p] == static_cast<std::uint32_t>(match_of_true[t - 1] + 1)) ++both[t - 1];
    else if (labels[p] == 0) ++unassigned;
    else ++elsewhere;
  }
  auto share = [](std::size_t a, std::size_t b) { return b ? static_cast<double>(a) / static_cast<double>(b) : 0.0; };
  s.tree_points_elsewhere = share(elsewhere, tree_points);
  s.tree_points_unassigned = share(unassigned, tree_points);
  s.others_in_trees = share(others_in, others);
  double sum = 0;
  for (std::size_t t = 0; t < plot.stems.size(); ++t) {
    if (match_of_true[t] < 0) continue;
    const std::size_t uni = in_true[t] + in_found[match_of_true[t] + 1] - both[t];
    sum += uni ? static_cast<double>(both[t]) / static_cast<double>(uni) : 0.0;
  }
  s.mean_iou = plot.stems.empty() ? 0.0 : sum / static_cast<double>(plot.stems.size());
  return s;
}

}  // namespace treeskel::eval
