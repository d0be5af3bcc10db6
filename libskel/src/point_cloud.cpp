#include "treeskel/point_cloud.h"

#include <Eigen/Eigenvalues>

namespace treeskel {

Eigen::AlignedBox3d bounding_box(const PointCloud& cloud) {
  Eigen::AlignedBox3d box;
  for (const auto& p : cloud.positions) box.extend(p);
  return box;
}

void append_point(PointCloud& to, const PointCloud& from, std::size_t p) {
  to.positions.push_back(from.positions[p]);
  if (from.has_normals()) to.normals.push_back(from.normals[p]);
  if (from.has_colors()) to.colors.push_back(from.colors[p]);
  if (!from.classes.empty()) to.classes.push_back(from.classes[p]);
}

void recentre_offset(PointCloud& cloud) {
  if (cloud.empty()) return;
  const Eigen::Vector3d shift = bounding_box(cloud).min();
  for (auto& p : cloud.positions) p -= shift;
  cloud.offset += shift;
}

CloudShape classify_shape(const PointCloud& cloud, double relative_tolerance) {
  if (cloud.empty()) return CloudShape::empty;
  const Eigen::AlignedBox3d box = bounding_box(cloud);
  if (box.sizes().maxCoeff() <= 0.0) return CloudShape::identical;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : cloud.positions) mean += p;
  mean /= static_cast<double>(cloud.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : cloud.positions) {
    const Eigen::Vector3d d = p - mean;
    cov.noalias() += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  const Eigen::Vector3d ev = eig.eigenvalues();  // ascending
  if (ev(1) <= relative_tolerance * relative_tolerance * ev(2)) return CloudShape::collinear;
  return CloudShape::ok;
}

}  // namespace treeskel
