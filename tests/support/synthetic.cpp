#include "support/synthetic.h"

#include <Eigen/Geometry>

#include <cstdlib>
#include <filesystem>
#include <random>
#include <stdexcept>

namespace treeskel::test {

namespace fs = std::filesystem;

double distance_to_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

PointCloud sample_cylinders(const std::vector<Cylinder>& cylinders, const SampleOptions& options) {
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<double> area;
  double total = 0.0;
  for (const auto& c : cylinders) {
    area.push_back(2.0 * M_PI * c.radius * (c.b - c.a).norm());
    total += area.back();
  }
  auto inside_other = [&](const Eigen::Vector3d& p, std::size_t self) {
    for (std::size_t k = 0; k < cylinders.size(); ++k) {
      if (k == self) continue;
      const auto& c = cylinders[k];
      const Eigen::Vector3d axis = c.b - c.a;
      const double t = (p - c.a).dot(axis) / axis.squaredNorm();
      if (t < 0.0 || t > 1.0) continue;
      if ((p - (c.a + t * axis)).norm() < c.radius) return true;
    }
    return false;
  };
  PointCloud cloud;
  std::size_t guard = 0;
  while (cloud.size() < options.points) {
    if (++guard > options.points * 200) throw std::runtime_error("sample_cylinders: cannot place the points");
    double pick = unit(rng) * total;
    std::size_t k = 0;
    while (k + 1 < cylinders.size() && pick > area[k]) pick -= area[k++];
    const auto& c = cylinders[k];
    const Eigen::Vector3d axis = (c.b - c.a).normalized();
    const Eigen::Vector3d u = axis.unitOrthogonal(), v = axis.cross(u);
    const double angle = unit(rng) * 2.0 * M_PI, t = unit(rng);
    const Eigen::Vector3d normal = std::cos(angle) * u + std::sin(angle) * v;
    if (options.facing && normal.dot(*options.facing) < 0.0) continue;
    const double r = c.radius + (options.noise > 0.0 ? options.noise * gauss(rng) : 0.0);
    const Eigen::Vector3d p = c.a + t * (c.b - c.a) + r * normal;
    if (inside_other(p, k)) continue;
    cloud.positions.push_back(p);
  }
  return cloud;
}

double mean_distance_to_axis(const Skeleton& skeleton, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  double sum = 0.0;
  for (NodeId v = 0; v < skeleton.node_count(); ++v)
    sum += distance_to_segment(skeleton[v].position + skeleton.offset, a, b);
  return sum / static_cast<double>(skeleton.node_count());
}

std::string data_file(const std::string& name) { return std::string(TREESKEL_TEST_DATA) + "/" + name; }

TempDir::TempDir() {
  std::string pattern = (fs::temp_directory_path() / "treeskel-test-XXXXXX").string();
  if (!::mkdtemp(pattern.data())) throw std::runtime_error("cannot create a temporary folder");
  root_ = pattern;
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(root_, ec);
}

std::string TempDir::path(const std::string& name) const { return (fs::path(root_) / name).string(); }

}  // namespace treeskel::test
