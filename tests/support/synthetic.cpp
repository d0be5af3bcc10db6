#include "support/synthetic.h"

#include <Eigen/Geometry>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace treeskel::test {

namespace fs = std::filesystem;

double mean_distance_to_axis(const Skeleton& skeleton, const eval::Cylinder& cylinder) {
  double sum = 0.0;
  for (NodeId v = 0; v < skeleton.node_count(); ++v)
    sum += eval::distance_to_axis(cylinder, skeleton[v].position + skeleton.offset);
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
