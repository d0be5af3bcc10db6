#include "treeskel/eval/tree_generator.h"

#include <Eigen/Geometry>

#include <cmath>
#include <random>

namespace treeskel::eval {

namespace {

struct Grower {
  const GrowOptions& options;
  std::mt19937_64 rng;
  GrownTree tree;

  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }

  /// Grows one branch from `start` along `direction`; returns nothing, appends cylinders.
  void branch(Eigen::Vector3d start, Eigen::Vector3d direction, double length, double radius, int order, int parent) {
    const int side = order == 0 ? options.branches
                                : static_cast<int>(std::lround(options.branches * std::pow(0.7, order) * uniform(0.7, 1.3)));
    const double step = options.segment_length * std::pow(options.length_ratio, 0.5 * order);
    const int segments = std::max(2, static_cast<int>(std::ceil(length / step)));
    // Where the side branches leave, as segment indices in the upper part of the branch.
    std::vector<int> forks;
    if (order < options.orders)
      for (int s = 0; s < side; ++s) forks.push_back(static_cast<int>(segments * uniform(order == 0 ? 0.35 : 0.2, 0.95)));
    std::sort(forks.begin(), forks.end());
    // The tip keeps a share of the cross section; each side branch takes the rest in pieces.
    const double tip_radius = radius * 0.25;
    double area = radius * radius;
    const double side_area = (area - tip_radius * tip_radius) / std::max<std::size_t>(forks.size() + 1, 1);
    double r = radius;
    Eigen::Vector3d p = start, d = direction.normalized();
    int previous = parent;
    std::size_t next_fork = 0;
    for (int s = 0; s < segments; ++s) {
      // Taper within a segment; lose a side branch's share at each fork.
      double r_end = std::sqrt(std::max(area - side_area * 0.5 / segments, tip_radius * tip_radius));
      area = r_end * r_end;
      const Eigen::Vector3d q = p + d * (length / segments);
      tree.cylinders.push_back({p, q, r, r_end});
      tree.parent.push_back(previous);
      const int self = static_cast<int>(tree.cylinders.size()) - 1;
      while (next_fork < forks.size() && forks[next_fork] == s) {
        const double child_area = std::min(side_area, 0.8 * area);
        const double child_radius = std::sqrt(child_area);
        area = std::max(area - child_area, tip_radius * tip_radius);
        const Eigen::Vector3d axis = d.unitOrthogonal();
        const double azimuth = uniform(0.0, 2.0 * M_PI), angle = uniform(30.0, 60.0) * M_PI / 180.0;
        const Eigen::Vector3d side_dir =
            Eigen::AngleAxisd(azimuth, d) * (Eigen::AngleAxisd(angle, axis) * d);
        // Plant trees grow up: lift side branches a little toward +z.
        const Eigen::Vector3d grown = (side_dir + 0.3 * Eigen::Vector3d::UnitZ()).normalized();
        branch(q, grown, length * options.length_ratio * uniform(0.8, 1.2), child_radius, order + 1, self);
        ++next_fork;
      }
      r = std::sqrt(area);  // the continuation starts with what the side branches left (pipe model)
      // Bend: a small random turn, and a slight pull upward.
      const Eigen::Vector3d turn_axis = Eigen::AngleAxisd(uniform(0.0, 2.0 * M_PI), d) * d.unitOrthogonal();
      d = (Eigen::AngleAxisd(options.bend * uniform(-1.0, 1.0), turn_axis) * d + 0.02 * Eigen::Vector3d::UnitZ()).normalized();
      p = q;
      previous = self;
    }
  }
};

}  // namespace

GrownTree grow_tree(const GrowOptions& options) {
  Grower g{options, std::mt19937_64(options.seed), {}};
  g.branch(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), options.height, options.trunk_radius, 0, -1);
  return std::move(g.tree);
}

}  // namespace treeskel::eval
