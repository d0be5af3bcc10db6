// Helpers shared by the tests: synthetic shapes with known skeletons, bundled data, temporary folders.
#pragma once

#include "treeskel/eval/cylinders.h"
#include "treeskel/point_cloud.h"
#include "treeskel/skeleton.h"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace treeskel::test {

/// A cylinder of constant radius.
inline eval::Cylinder tube(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius) {
  return {a, b, radius, radius};
}

/// Mean distance of the skeleton's nodes (local frame + offset) to the cylinder's axis segment.
double mean_distance_to_axis(const Skeleton& skeleton, const eval::Cylinder& cylinder);

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
