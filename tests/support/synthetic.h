// Synthetic shapes with known skeletons for the tests, and helpers to measure against them.
#pragma once

#include "treeskel/point_cloud.h"
#include "treeskel/skeleton.h"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace treeskel::test {

/// A solid cylinder from `a` to `b`.
struct Cylinder {
  Eigen::Vector3d a, b;
  double radius;
};

struct SampleOptions {
  std::size_t points = 10000;
  unsigned seed = 1;
  double noise = 0.0;  ///< Gaussian noise along the surface normal, standard deviation
  /// When set, only the side of each cylinder that faces this direction is kept (a single scanner).
  std::optional<Eigen::Vector3d> facing;
};

/// Points on the lateral surfaces of the cylinders, spread by area, without the points that fall
/// inside another cylinder (no points inside the wood at junctions). Deterministic for a seed.
PointCloud sample_cylinders(const std::vector<Cylinder>& cylinders, const SampleOptions& options);

/// Distance from p to the segment [a, b].
double distance_to_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b);

/// Mean distance of the skeleton's nodes (local frame + offset) to the segment.
double mean_distance_to_axis(const Skeleton& skeleton, const Eigen::Vector3d& a, const Eigen::Vector3d& b);

/// Path of a bundled example cloud.
std::string data_file(const std::string& name);

/// A fresh empty folder for a test's files, removed with its content when the object dies.
class TempDir {
public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string path(const std::string& name) const;
  const std::string& root() const { return root_; }

private:
  std::string root_;
};

}  // namespace treeskel::test
