// pypetree's artificial tree (cjauvin/pypetree): a cloud sampled on an L-system tree and the exact
// skeleton that generated it, radii included. Shared by the accuracy and radius benchmarks.
#pragma once

#include "treeskel/io/point_cloud_io.h"
#include "treeskel/point_cloud.h"
#include "treeskel/skeleton.h"

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace treeskel::bench {

/// Loads artificial_cloud.asc and artificial_model.csv from `dir` (Y up). With `normalise`, both are
/// scaled so that the cloud's longest side is 1 and the offset is dropped, like the synthetic set.
/// Returns false if the files are not there.
inline bool load_pypetree(const std::string& dir, PointCloud& cloud, Skeleton& truth, bool normalise = true) {
  const std::filesystem::path cloud_path = std::filesystem::path(dir) / "artificial_cloud.asc", model_path = std::filesystem::path(dir) / "artificial_model.csv";
  if (!std::filesystem::exists(cloud_path) || !std::filesystem::exists(model_path)) return false;
  cloud = io::read_point_cloud(cloud_path);
  std::ifstream in(model_path);
  std::string line;
  std::getline(in, line);
  std::map<long, NodeId> ids;
  std::vector<std::pair<long, long>> links;
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    if (f.size() < 6) continue;
    SkeletonNode n;
    n.position = Eigen::Vector3d(std::stod(f[2]), std::stod(f[3]), std::stod(f[4])) - cloud.offset;
    n.radius = std::stod(f[5]);
    ids[std::stol(f[0])] = add_node(truth, n);
    if (!f[1].empty()) links.emplace_back(std::stol(f[0]), std::stol(f[1]));
    else truth.root = ids[std::stol(f[0])];
  }
  for (const auto& [a, b] : links) boost::add_edge(ids.at(a), ids.at(b), truth.graph);
  truth.offset = cloud.offset;
  if (!normalise) return true;
  // Normalise both like the synthetic set: longest side of the cloud's box is 1.
  const double size = bounding_box(cloud).sizes().maxCoeff();
  for (auto& p : cloud.positions) p /= size;
  for (NodeId v = 0; v < truth.node_count(); ++v) {
    truth[v].position /= size;
    truth[v].radius /= size;
  }
  cloud.offset.setZero();  // both frames now start at the cloud's minimum corner
  truth.offset.setZero();
  return true;
}


}  // namespace treeskel::bench
