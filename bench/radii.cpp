// How close the fitted radii come to known ones.
//
//   bench_radii [--seed S] [--pypetree DIR] [--archi DIR] [--exponent E] [--stem-share-bound K] [--stiffness F]
//               [--stub-length K] [--prune-radius P] [--fork-margin M]
//   (E: Leonardo exponent, 2 by default; F: the limbs' stiffness, `treeskel model --stiffness`; K, P and M:
//   the model's `--stub-length`, `--prune-radius` and `--fork-margin`)
//
// - The paper's six synthetic trees (eval::make_paper_tree): the clean cloud of each (the paper's
//   first point count) is skeletonized, radii fitted, and compared with the generating cylinders.
// - pypetree's artificial tree (exact model with radii), Y up: at the exponent asked for, and at the
//   exponent its own forks follow.
// - aRchi's Tree_1 (real TLS): trunk diameter at 1.3 m above the lowest point, and the total wood
//   volume, against the TreeQSM cylinder table shipped with it (Tree_1_TreeQSM.txt: radius, length,
//   start xyz, axis xyz, parent, extension, added, unmodified radius, branch, order, ...).
// Radius error: the true skeleton is sampled every 1/1000 of the tree's size along its length; at
// each sample, the fitted radius where the fitted skeleton passes nearest (interpolated along its
// edge) against the true radius there. Samples within a true radius of a fork are left out, and
// samples with no fitted branch within two true radii (plus 1% of the tree's size) count as not
// covered.
#include "pypetree.h"
#include "treeskel/eval/paper_trees.h"
#include "treeskel/geometry.h"
#include "treeskel/io/point_cloud_io.h"
#include "treeskel/modeling/measurements.h"
#include "treeskel/modeling/radii.h"
#include "treeskel/pipeline.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

using namespace treeskel;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct RadiusError {
  double mean = 0.0, median = 0.0, coverage = 0.0, trunk = 0.0;
};

/// Compares radii of `fitted` with `truth` (both in the same frame, offsets included). The true
/// skeleton is sampled evenly along its length (a sample every 1/1000 of the tree's size, the radius
/// interpolated along each true edge, as both generators taper it), leaving out samples within a
/// true radius of a fork, where branches overlap.
RadiusError compare(const Skeleton& fitted, const Skeleton& truth) {
  const auto& fg = fitted.graph;
  const auto& tg = truth.graph;
  Eigen::AlignedBox3d box;
  for (NodeId v = 0; v < truth.node_count(); ++v) box.extend(tg[v].position + truth.offset);
  const double slack = 0.01 * box.sizes().maxCoeff(), step = 0.001 * box.sizes().maxCoeff();
  std::vector<double> errors;
  std::size_t considered = 0;
  auto sample = [&](const Eigen::Vector3d& p, double true_radius) {
    ++considered;
    double best = std::numeric_limits<double>::infinity(), radius = 0.0;
    for (auto [it, end] = boost::edges(fg); it != end; ++it) {
      const NodeId a = boost::source(*it, fg), b = boost::target(*it, fg);
      const Eigen::Vector3d pa = fg[a].position + fitted.offset, pb = fg[b].position + fitted.offset;
      const double d = point_segment_distance(p, pa, pb);
      if (d < best) {
        best = d;
        const Eigen::Vector3d ab = pb - pa;
        const double t = ab.squaredNorm() > 0 ? std::clamp((p - pa).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
        radius = (1 - t) * fg[a].radius + t * fg[b].radius;
      }
    }
    if (best > 2.0 * true_radius + slack) return;
    errors.push_back(std::abs(radius - true_radius) / true_radius);
  };
  for (auto [it, end] = boost::edges(tg); it != end; ++it) {
    const NodeId a = boost::source(*it, tg), b = boost::target(*it, tg);
    const Eigen::Vector3d pa = tg[a].position + truth.offset, pb = tg[b].position + truth.offset;
    const double length = (pb - pa).norm();
    const auto count = static_cast<int>(std::ceil(length / step));
    for (int k = 0; k < count; ++k) {
      const double t = (k + 0.5) / count;
      const Eigen::Vector3d p = pa + t * (pb - pa);
      const double r = (1 - t) * tg[a].radius + t * tg[b].radius;
      if ((boost::degree(a, tg) > 2 && t * length < tg[a].radius) || (boost::degree(b, tg) > 2 && (1 - t) * length < tg[b].radius))
        continue;
      sample(p, r);
    }
  }
  RadiusError e;
  if (errors.empty()) return e;
  for (double x : errors) e.mean += x;
  e.mean /= static_cast<double>(errors.size());
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  e.median = errors[errors.size() / 2];
  e.coverage = static_cast<double>(errors.size()) / static_cast<double>(considered);
  return e;
}

/// The Leonardo exponent the true skeleton's forks follow: at each fork, the e with
/// sum over children of (r_child / r_fork)^e = 1, where each child's radius is that of the next node
/// along it; the median over the forks.
double own_exponent(const Skeleton& truth) {
  const auto& g = truth.graph;
  std::vector<double> exponents;
  for (NodeId v = 0; v < truth.node_count(); ++v) {
    if (boost::degree(v, g) < 3) continue;
    std::vector<double> ratios;
    for (auto [it, end] = boost::adjacent_vertices(v, g); it != end; ++it)
      if (g[*it].radius < g[v].radius) ratios.push_back(g[*it].radius / g[v].radius);  // children are thinner
    if (ratios.size() < 2) continue;
    auto excess = [&](double e) {
      double sum = -1.0;
      for (double r : ratios) sum += std::pow(r, e);
      return sum;  // falls as e grows
    };
    double lo = 0.5, hi = 8.0;
    if (excess(lo) < 0.0 || excess(hi) > 0.0) continue;
    for (int i = 0; i < 60; ++i) (excess(0.5 * (lo + hi)) > 0.0 ? lo : hi) = 0.5 * (lo + hi);
    exponents.push_back(0.5 * (lo + hi));
  }
  if (exponents.empty()) return std::nan("");
  std::nth_element(exponents.begin(), exponents.begin() + exponents.size() / 2, exponents.end());
  return exponents[exponents.size() / 2];
}

/// The cylinder rows of a TreeQSM table (radius, length, start xyz, axis xyz, parent, extension,
/// added, unmodified radius, branch, order, ...): every line of at least 14 numbers.
std::vector<std::vector<double>> treeqsm_rows(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::vector<double>> rows;
  for (std::string line; std::getline(in, line);) {
    std::istringstream s(line);
    std::vector<double> f;
    for (double x; s >> x;) f.push_back(x);
    if (f.size() >= 14) rows.push_back(std::move(f));
  }
  return rows;
}

/// Total volume of a TreeQSM table's cylinders.
double treeqsm_volume(const std::vector<std::vector<double>>& rows) {
  double volume = 0.0;
  for (const auto& f : rows) volume += kPi * f[0] * f[0] * f[1];
  return volume;
}

/// The trunk diameter of a TreeQSM table at `height` above `base` (z up), or NaN.
double treeqsm_diameter(const std::vector<std::vector<double>>& rows, double base, double height) {
  for (const auto& f : rows) {
    if (f[12] != 1.0) continue;  // branch 1 is the trunk
    const double r = f[0], length = f[1], z0 = f[4], dz = f[7];
    const double z1 = z0 + length * dz;
    if ((z0 - base - height) * (z1 - base - height) <= 0.0) return 2.0 * r;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

int main(int argc, char** argv) {
  std::uint64_t seed = 1;
  std::string pypetree, archi;
  modeling::RadiusOptions radius_options;
  SkeletonOptions skeleton_options;  // pruned as `treeskel model` prunes
  modeling::use_model_pruning(skeleton_options.prune);
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--seed" && i + 1 < argc) seed = std::stoull(argv[++i]);
    else if (a == "--pypetree" && i + 1 < argc) pypetree = argv[++i];
    else if (a == "--archi" && i + 1 < argc) archi = argv[++i];
    else if (a == "--exponent" && i + 1 < argc) radius_options.exponent = std::stod(argv[++i]);
    else if (a == "--stem-share-bound" && i + 1 < argc) radius_options.max_share_over_pipe = std::stod(argv[++i]);
    else if (a == "--stiffness" && i + 1 < argc) radius_options.stiffness = std::stod(argv[++i]);
    else if (a == "--stub-length" && i + 1 < argc) radius_options.stub_length = std::stod(argv[++i]);
    else if (a == "--fork-margin" && i + 1 < argc) radius_options.fork_margin = std::stod(argv[++i]);
    else if (a == "--prune-radius" && i + 1 < argc) skeleton_options.prune.radius_factor = std::stod(argv[++i]);
    else {
      std::cout << "usage: bench_radii [--seed S] [--pypetree DIR] [--archi DIR] [--exponent E] [--stem-share-bound K] [--stiffness F] [--stub-length K] [--prune-radius P] [--fork-margin M]\n";
      return a == "-h" || a == "--help" ? 0 : 2;
    }
  }
  std::printf("| tree | cloud | mean radius error | median | length covered |\n|---|---|---:|---:|---:|\n");
  double sum = 0.0;
  for (int index = 1; index <= 6; ++index) {
    const eval::GroundTruth truth = eval::make_paper_tree(index, seed);
    const auto clouds = eval::make_paper_clouds(truth, index, seed);
    const auto& clean = clouds.front();
    Skeleton s = extract_skeleton(clean.cloud, skeleton_options);
    modeling::fit_radii(s, &clean.cloud, radius_options);
    const RadiusError e = compare(s, truth.skeleton);
    sum += e.mean;
    std::printf("| tree%d | %s | %.1f%% | %.1f%% | %.0f%% |\n", index, clean.name.c_str(), 100 * e.mean, 100 * e.median,
                100 * e.coverage);
  }
  std::printf("| **mean** | | **%.1f%%** | | |\n\n", 100 * sum / 6);

  if (!pypetree.empty()) {
    PointCloud cloud;
    Skeleton truth;
    if (!bench::load_pypetree(pypetree, cloud, truth, false)) {
      std::cerr << "bench_radii: no pypetree files in " << pypetree << '\n';
      return 1;
    }
    SkeletonOptions o = skeleton_options;
    o.root.up = Eigen::Vector3d::UnitY();
    const Skeleton extracted = extract_skeleton(cloud, o);
    auto error_at = [&](const modeling::RadiusOptions& options) {
      Skeleton s = extracted;
      modeling::fit_radii(s, &cloud, options);
      return compare(s, truth);
    };
    const RadiusError e = error_at(radius_options);
    std::printf("pypetree artificial tree (%zu points), exponent %.2f: mean radius error %.1f%%, median %.1f%%, %.0f%% of the length covered\n",
                cloud.size(), radius_options.exponent, 100 * e.mean, 100 * e.median, 100 * e.coverage);
    // Its generator does not follow e = 2: each child starts as thick as the fork and tapers along
    // its own length, so the cross section grows at every fork.
    modeling::RadiusOptions own = radius_options;
    own.exponent = own_exponent(truth);
    const RadiusError o_e = error_at(own);
    std::printf("  with the exponent of its own forks, %.2f (median over them): mean radius error %.1f%%, median %.1f%%\n\n",
                own.exponent, 100 * o_e.mean, 100 * o_e.median);
  }
  if (!archi.empty()) {
    const std::string las = archi + "/Tree_1_point_cloud.las", qsm = archi + "/Tree_1_TreeQSM.txt";
    const PointCloud cloud = io::read_point_cloud(las);
    Skeleton s = extract_skeleton(cloud, skeleton_options);
    modeling::fit_radii(s, &cloud, radius_options);
    const modeling::TreeMeasurements m = modeling::measure_tree(s, &cloud);
    double base = std::numeric_limits<double>::infinity();
    for (const auto& p : cloud.positions) base = std::min(base, p.z() + cloud.offset.z());
    const auto rows = treeqsm_rows(qsm);
    const double reference = treeqsm_diameter(rows, base, 1.3);
    std::printf("aRchi Tree_1 (%zu points): DBH %.3f m, TreeQSM %.3f m, difference %+.1f%%\n", cloud.size(),
                m.dbh ? *m.dbh : std::nan(""), reference, 100.0 * ((m.dbh ? *m.dbh : 0.0) / reference - 1.0));
    const double qsm_volume = treeqsm_volume(rows);
    std::printf("  wood volume %.2f m3, TreeQSM %.2f m3, difference %+.1f%%\n", m.volume, qsm_volume,
                100.0 * (m.volume / qsm_volume - 1.0));
  }
  return 0;
}
