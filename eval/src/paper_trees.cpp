#include "treeskel/eval/paper_trees.h"

#include "treeskel/geometry.h"

#include "treeskel/error.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <random>

namespace treeskel::eval {

namespace {

constexpr double kTaper = 1.06;         // radius at a branch's base / radius at its end
constexpr double kTrunkRadius = 0.028;  // trunk radius at the base, in units of the longest side
constexpr double kNodeSpacing = 0.01;   // ground-truth polyline spacing, same units

/// A branch between two forks (or the root and a fork, or a fork and a tip): a quadratic Bezier curve.
struct Branch {
  int parent = -1;
  std::vector<int> children;
  Eigen::Vector3d start, control, end;
  double length = 0.0;
  double r_start = 0.0, r_end = 0.0;

  Eigen::Vector3d at(double s) const { return (1 - s) * (1 - s) * start + 2 * s * (1 - s) * control + s * s * end; }
  Eigen::Vector3d end_direction() const { return (end - control).normalized(); }
};

class TreeGrower {
public:
  TreeGrower(const TreeShape& shape, std::uint64_t seed) : shape_(shape), rng_(seed) {}

  std::vector<Branch> grow() {
    Branch trunk;
    trunk.start = Eigen::Vector3d::Zero();
    trunk.length = 0.32;
    trunk.end = trunk.start + trunk.length * Eigen::Vector3d::UnitZ();
    trunk.control = 0.5 * (trunk.start + trunk.end) + bend(Eigen::Vector3d::UnitZ(), trunk.length);
    branches_.push_back(trunk);

    // Extra children beyond a binary fork, spread over the forks (at most 2 extra, 4 children, each).
    const int forks = shape_.branch_points;
    int extra = shape_.endpoints - 2 - forks;
    if (forks < 1 || extra < 0 || extra > 2 * forks)
      throw OptionError("a tree with " + std::to_string(forks) + " branch points cannot have " +
                        std::to_string(shape_.endpoints) + " endpoints (2 + branch points to 2 + 3 x branch points)");
    std::vector<int> extra_at(forks, 0);
    while (extra > 0) {
      const int f = uniform_int(0, forks - 1);
      if (extra_at[f] < 2) {
        ++extra_at[f];
        --extra;
      }
    }
    // Apical dominance: the next fork grows on a vigorous (long) open tip, with some disorder, so that
    // forks spread over the crown instead of piling up on short twigs.
    std::vector<int> open{0};
    for (int f = 0; f < forks; ++f) {
      int pick = 0;
      double best = -1.0;
      for (std::size_t i = 0; i < open.size(); ++i) {
        const double vigour = branches_[open[i]].length * uniform(0.7, 1.3);
        if (vigour > best) best = vigour, pick = static_cast<int>(i);
      }
      const int b = open[pick];
      open.erase(open.begin() + pick);
      for (int c : fork(b, 2 + extra_at[f])) open.push_back(c);
    }
    assign_radii();
    return branches_;
  }

private:
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  int uniform_int(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }

  /// Offset of a Bezier control point from the chord's middle: a gentle bend.
  Eigen::Vector3d bend(const Eigen::Vector3d& direction, double length) {
    const Eigen::Vector3d side = Eigen::AngleAxisd(uniform(0.0, 2 * M_PI), direction) * direction.unitOrthogonal();
    return side * length * uniform(-0.08, 0.08);
  }

  /// Smallest distance from the new chord (beyond its first 30%) to the chords of the other branches
  /// (its parent and siblings, which share its start, are checked beyond their first 30% too).
  double clearance(const Eigen::Vector3d& a, const Eigen::Vector3d& b, int parent) const {
    double best = 1e9;
    for (std::size_t i = 0; i < branches_.size(); ++i) {
      const auto& o = branches_[i];
      const bool shares_start = static_cast<int>(i) == parent || o.parent == parent;
      const Eigen::Vector3d from = shares_start ? o.start + 0.3 * (o.end - o.start) : o.start;
      const Eigen::Vector3d to = static_cast<int>(i) == parent ? o.start + 0.7 * (o.end - o.start) : o.end;
      for (int k = 3; k <= 10; ++k) best = std::min(best, point_segment_distance(a + (b - a) * (k / 10.0), from, to));
    }
    return best;
  }

  std::vector<int> fork(int b, int k) {
    const Branch parent = branches_[b];
    const Eigen::Vector3d d = parent.end_direction();
    const double azimuth0 = uniform(0.0, 2 * M_PI);
    std::vector<int> made;
    for (int j = 0; j < k; ++j) {
      Branch child;
      child.parent = b;
      child.start = parent.end;
      Eigen::Vector3d best_dir = d;
      double best_length = 0.0, best_clear = -1.0;
      for (int attempt = 0; attempt < shape_.attempts; ++attempt) {
        const bool leader = j == 0;
        const auto& angles = leader ? shape_.leader_angle : shape_.side_angle;
        const double angle = uniform(angles[0], angles[1]) * M_PI / 180.0;
        const double azimuth =
            leader ? uniform(0.0, 2 * M_PI) : azimuth0 + 2 * M_PI * (j - 1) / std::max(1, k - 1) + uniform(-0.4, 0.4);
        const Eigen::Vector3d tilt_axis = Eigen::AngleAxisd(azimuth, d) * d.unitOrthogonal();
        Eigen::Vector3d dir = Eigen::AngleAxisd(angle, tilt_axis) * d;
        if (!leader) dir = (dir + shape_.lift * Eigen::Vector3d::UnitZ()).normalized();  // branches turn upward
        const auto& ratio = leader ? shape_.leader_length : shape_.side_length;
        const double length = parent.length * uniform(ratio[0], ratio[1]);
        const double clear = clearance(child.start, child.start + dir * length, b);
        if (clear > best_clear) {
          best_clear = clear;
          best_dir = dir;
          best_length = length;
        }
        if (clear > shape_.clearance * length) break;
      }
      child.length = best_length;
      child.end = child.start + best_dir * best_length;
      child.control = 0.5 * (child.start + child.end) + bend(best_dir, best_length);
      branches_.push_back(child);
      made.push_back(static_cast<int>(branches_.size()) - 1);
      branches_[b].children.push_back(made.back());
    }
    return made;
  }

  /// Pipe model from the tips down: a fork's cross section is the sum of its children's.
  void assign_radii() {
    for (int i = static_cast<int>(branches_.size()) - 1; i >= 0; --i) {
      auto& br = branches_[i];
      if (br.children.empty()) {
        br.r_end = 1.0;
      } else {
        double area = 0.0;
        for (int c : br.children) area += branches_[c].r_start * branches_[c].r_start;
        br.r_end = std::sqrt(area);
      }
      br.r_start = br.r_end * kTaper;
    }
  }

  const TreeShape& shape_;
  std::mt19937_64 rng_;
  std::vector<Branch> branches_;
};

}  // namespace

const std::array<PaperTreeSpec, 6>& paper_tree_specs() {
  static const std::array<PaperTreeSpec, 6> specs{{{1, 19, 22, {14045, 28189, 7088}},
                                                   {2, 11, 13, {16647, 33327, 8425}},
                                                   {3, 23, 25, {14830, 29821, 9037}},
                                                   {4, 65, 87, {13736, 28117, 8375}},
                                                   {5, 110, 154, {11433, 23011, 45680}},
                                                   {6, 58, 89, {11046, 21792, 44003}}}};
  return specs;
}

std::string degradation_name(Degradation d) {
  switch (d) {
    case Degradation::points: return "points";
    case Degradation::missing: return "missing";
    case Degradation::noise: return "noise";
    case Degradation::vdensity: return "vdensity";
  }
  return "";
}

GroundTruth make_paper_tree(int index, std::uint64_t seed) {
  if (index < 1 || index > 6) throw OptionError("paper trees are numbered 1 to 6, got " + std::to_string(index));
  const PaperTreeSpec& spec = paper_tree_specs()[index - 1];
  TreeShape shape;
  shape.branch_points = spec.branch_points;
  shape.endpoints = spec.endpoints;
  return grow_truth(shape, seed * 1000003ULL + static_cast<std::uint64_t>(spec.index));
}

GroundTruth grow_truth(const TreeShape& shape, std::uint64_t seed) {
  std::vector<Branch> branches = TreeGrower(shape, seed).grow();

  // Normalise: radii so that the trunk has the chosen share of the size, then positions and radii so
  // that the longest side of the box around the wood is 1, its minimum corner at the origin.
  Eigen::AlignedBox3d box;
  for (const auto& b : branches)
    for (int k = 0; k <= 16; ++k) box.extend(b.at(k / 16.0));
  double size = box.sizes().maxCoeff();
  const double radius_scale = kTrunkRadius * size / branches[0].r_start;
  for (auto& b : branches) {
    b.r_start *= radius_scale;
    b.r_end *= radius_scale;
  }
  Eigen::AlignedBox3d wood;
  for (const auto& b : branches)
    for (int k = 0; k <= 16; ++k) {
      const double r = b.r_start + (k / 16.0) * (b.r_end - b.r_start);
      wood.extend(b.at(k / 16.0) - Eigen::Vector3d::Constant(r));
      wood.extend(b.at(k / 16.0) + Eigen::Vector3d::Constant(r));
    }
  size = wood.sizes().maxCoeff();
  const Eigen::Vector3d corner = wood.min();
  auto normalise = [&](const Eigen::Vector3d& p) -> Eigen::Vector3d { return (p - corner) / size; };

  GroundTruth truth;
  Skeleton& s = truth.skeleton;
  std::vector<NodeId> end_node(branches.size());
  for (std::size_t i = 0; i < branches.size(); ++i) {
    const auto& b = branches[i];
    const double length = b.length / size;
    const int pieces = std::max(3, static_cast<int>(std::ceil(length / kNodeSpacing)));
    NodeId previous;
    if (b.parent < 0) {
      SkeletonNode root;
      root.position = normalise(b.start);
      root.radius = b.r_start / size;
      previous = add_node(s, root);
      s.root = previous;
    } else {
      previous = end_node[b.parent];
    }
    for (int k = 1; k <= pieces; ++k) {
      const double t = static_cast<double>(k) / pieces;
      SkeletonNode node;
      node.position = normalise(b.at(t));
      node.radius = (b.r_start + t * (b.r_end - b.r_start)) / size;
      const NodeId v = add_node(s, node);
      boost::add_edge(previous, v, s.graph);
      const double r_prev = k == 1 ? b.r_start / size : s[previous].radius;
      truth.cylinders.push_back({s[previous].position, node.position, r_prev, node.radius});
      previous = v;
    }
    end_node[i] = previous;
  }
  return truth;
}

std::vector<PaperCloud> make_paper_clouds(const GroundTruth& truth, int index, std::uint64_t seed) {
  const PaperTreeSpec& spec = paper_tree_specs()[index - 1];
  const std::string tree = "tree" + std::to_string(index);
  const std::uint64_t base_seed = seed * 7919ULL + static_cast<std::uint64_t>(index) * 104729ULL;
  const std::size_t base = spec.counts[0];
  std::vector<PaperCloud> clouds;
  auto add = [&](std::string name, Degradation d, int variant, PointCloud cloud) {
    clouds.push_back({std::move(name), index, d, variant, std::move(cloud)});
  };
  std::mt19937_64 rng(base_seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);

  // Different numbers of points, in the paper's order.
  for (int v = 0; v < 3; ++v) {
    SurfaceSampling s;
    s.points = spec.counts[v];
    s.seed = base_seed + 1 + v;
    add(tree + "_" + std::to_string(spec.counts[v]), Degradation::points, v + 1, sample_cylinders(truth.cylinders, s));
  }
  // Missing data: what one scanner sees from one side, with holes where leaves or other trees hid it.
  Eigen::AlignedBox3d box;
  for (const auto& c : truth.cylinders) box.extend(c.a), box.extend(c.b);
  for (int v = 1; v <= 3; ++v) {
    const double azimuth = 2 * M_PI * (v - 1) / 3.0 + unit(rng) * 0.5;
    SurfaceSampling s;
    s.points = base + base / 2;
    s.seed = base_seed + 10 + v;
    s.facing = Eigen::Vector3d(std::cos(azimuth), std::sin(azimuth), 0.15).normalized();
    PointCloud seen = sample_cylinders(truth.cylinders, s);
    std::vector<std::pair<Eigen::Vector3d, double>> holes;
    for (int h = 0; h < 2 + 2 * v; ++h)
      holes.emplace_back(seen.positions[static_cast<std::size_t>(unit(rng) * seen.size()) % seen.size()],
                         0.02 + 0.03 * unit(rng));
    PointCloud kept;
    for (const auto& p : seen.positions) {
      if (kept.size() == base) break;
      if (std::none_of(holes.begin(), holes.end(), [&](const auto& h) { return (p - h.first).norm() < h.second; }))
        kept.positions.push_back(p);
    }
    add(tree + "_missing_" + std::to_string(v), Degradation::missing, v, std::move(kept));
  }
  // Noise: Gaussian noise across the surface and a share of outliers around the tree.
  for (int v = 1; v <= 3; ++v) {
    SurfaceSampling s;
    s.points = base;
    s.seed = base_seed + 20 + v;
    s.noise = 0.0015 * v;
    PointCloud noisy = sample_cylinders(truth.cylinders, s);
    const std::size_t outliers = base * v / 200;
    for (std::size_t o = 0; o < outliers; ++o)
      noisy.positions[static_cast<std::size_t>(unit(rng) * base) % base] =
          box.min() + (box.max() - box.min()).cwiseProduct(Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
    add(tree + "_noise_" + std::to_string(v), Degradation::noise, v, std::move(noisy));
  }
  // Varying density: waves of dense and sparse sampling across the tree.
  for (int v = 1; v <= 3; ++v) {
    SurfaceSampling s;
    s.points = base * 3;
    s.seed = base_seed + 30 + v;
    const PointCloud dense = sample_cylinders(truth.cylinders, s);
    const Eigen::Vector3d axis = Eigen::Vector3d(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5).normalized();
    const double phase = unit(rng) * 2 * M_PI, frequency = 1.0 + v;
    PointCloud kept;
    for (const auto& p : dense.positions) {
      if (kept.size() == base) break;
      const double keep = 0.08 + 0.92 * (0.5 + 0.5 * std::sin(2 * M_PI * frequency * p.dot(axis) + phase));
      if (unit(rng) < keep) kept.positions.push_back(p);
    }
    add(tree + "_vdensity_" + std::to_string(v), Degradation::vdensity, v, std::move(kept));
  }
  return clouds;
}

}  // namespace treeskel::eval
