// How close the fitted radii come to known ones.
//
//   bench_radii [--seed S] [--pypetree DIR] [--archi DIR] [--exponent E]   (E: Leonardo exponent, 2 by default)
//
// - The paper's six synthetic trees (eval::make_paper_tree): the clean cloud of each (the paper's
//   first point count) is skeletonized, radii fitted, and compared with the generating cylinders.
// - pypetree's artificial tree (exact model with radii), Y up.
// - aRchi's Tree_1 (real TLS): trunk diameter at 1.3 m above the lowest point, against the TreeQSM
//   cylinder table shipped with it (Tree_1_TreeQSM.txt: radius, length, start xyz, axis xyz, parent,
//   extension, added, unmodified radius, branch, order, ...).
// Radius error: at every node of the true skeleton that is not a fork, the fitted radius where the
// fitted skeleton passes nearest (interpolated along its edge) against the true radius; nodes with
// no fitted branch within two true radii (plus 1% of the tree's size) are counted as not covered.
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

struct RadiusError {
  double mean = 0.0, median = 0.0, coverage = 0.0, trunk = 0.0;
};

/// Compares radii of `fitted` with `truth` (both in the same frame, offsets included).
RadiusError compare(const Skeleton& fitted, const Skeleton& truth) {
  const auto& fg = fitted.graph;
  const auto& tg = truth.graph;
  Eigen::AlignedBox3d box;
  for (NodeId v = 0; v < truth.node_count(); ++v) box.extend(tg[v].position + truth.offset);
  const double slack = 0.01 * box.sizes().maxCoeff();
  std::vector<double> errors;
  std::size_t considered = 0;
  for (NodeId v = 0; v < truth.node_count(); ++v) {
    if (boost::degree(v, tg) > 2) continue;
    ++considered;
    const Eigen::Vector3d p = tg[v].position + truth.offset;
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
    if (best > 2.0 * tg[v].radius + slack) continue;
    errors.push_back(std::abs(radius - tg[v].radius) / tg[v].radius);
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

/// The trunk diameter of a TreeQSM table at `height` above `base` (z up), or NaN.
double treeqsm_diameter(const std::string& path, double base, double height) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::vector<double> f;
    for (double x; s >> x;) f.push_back(x);
    if (f.size() < 14 || f[12] != 1.0) continue;  // branch 1 is the trunk
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
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--seed" && i + 1 < argc) seed = std::stoull(argv[++i]);
    else if (a == "--pypetree" && i + 1 < argc) pypetree = argv[++i];
    else if (a == "--archi" && i + 1 < argc) archi = argv[++i];
    else if (a == "--exponent" && i + 1 < argc) radius_options.exponent = std::stod(argv[++i]);
    else {
      std::cout << "usage: bench_radii [--seed S] [--pypetree DIR] [--archi DIR] [--exponent E]\n";
      return a == "-h" || a == "--help" ? 0 : 2;
    }
  }
  std::printf("| tree | cloud | mean radius error | median | nodes covered |\n|---|---|---:|---:|---:|\n");
  double sum = 0.0;
  for (int index = 1; index <= 6; ++index) {
    const eval::GroundTruth truth = eval::make_paper_tree(index, seed);
    const auto clouds = eval::make_paper_clouds(truth, index, seed);
    const auto& clean = clouds.front();
    Skeleton s = extract_skeleton(clean.cloud);
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
    SkeletonOptions o;
    o.root.up = Eigen::Vector3d::UnitY();
    Skeleton s = extract_skeleton(cloud, o);
    modeling::fit_radii(s, &cloud, radius_options);
    const RadiusError e = compare(s, truth);
    std::printf("pypetree artificial tree (%zu points): mean radius error %.1f%%, median %.1f%%, %.0f%% of the nodes covered\n\n",
                cloud.size(), 100 * e.mean, 100 * e.median, 100 * e.coverage);
  }
  if (!archi.empty()) {
    const std::string las = archi + "/Tree_1_point_cloud.las", qsm = archi + "/Tree_1_TreeQSM.txt";
    const PointCloud cloud = io::read_point_cloud(las);
    Skeleton s = extract_skeleton(cloud);
    modeling::fit_radii(s, &cloud, radius_options);
    const modeling::TreeMeasurements m = modeling::measure_tree(s, &cloud);
    double base = std::numeric_limits<double>::infinity();
    for (const auto& p : cloud.positions) base = std::min(base, p.z() + cloud.offset.z());
    const double reference = treeqsm_diameter(qsm, base, 1.3);
    std::printf("aRchi Tree_1 (%zu points): DBH %.3f m, TreeQSM %.3f m, difference %+.1f%%\n", cloud.size(),
                m.dbh ? *m.dbh : std::nan(""), reference, 100.0 * ((m.dbh ? *m.dbh : 0.0) / reference - 1.0));
  }
  return 0;
}
