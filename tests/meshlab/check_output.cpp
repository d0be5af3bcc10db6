// Checks what meshlabserver saved after running the treeskel filters (used by tests/meshlab/meshlab_test.sh).
//   meshlab_check skeleton SKELETON.obj QUALITY.ply CLOUD   the layer is one tree, radii (quality) positive,
//                                                           nodes inside the cloud's box
//   meshlab_check mesh MESH CLOUD                           closed, manifold, one outward component without
//                                                           self-intersection, extent close to the cloud's
#include "treeskel/skeleton.h"
#include "treeskel/io/mesh_io.h"
#include "treeskel/io/point_cloud_io.h"
#include "treeskel/modeling/tree_mesh.h"

#include <Eigen/Geometry>

#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace treeskel;

[[noreturn]] void fail(const std::string& message) {
  std::cerr << "meshlab_check: " << message << '\n';
  std::exit(1);
}

Eigen::AlignedBox3d world_box(const PointCloud& cloud) {
  Eigen::AlignedBox3d box = bounding_box(cloud);
  return Eigen::AlignedBox3d(box.min() + cloud.offset, box.max() + cloud.offset);
}

int check_skeleton(const std::string& obj, const std::string& ply, const std::string& cloud_file) {
  std::ifstream in(obj);
  if (!in) fail("cannot read " + obj);
  std::vector<Eigen::Vector3d> nodes;
  std::vector<std::pair<long, long>> edges;
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::string tag;
    words >> tag;
    if (tag == "v") {
      Eigen::Vector3d p;
      words >> p.x() >> p.y() >> p.z();
      nodes.push_back(p);
    } else if (tag == "l") {
      long a = 0, b = 0;
      words >> a >> b;
      edges.emplace_back(a - 1, b - 1);
    }
  }
  if (nodes.size() < 10) fail(obj + ": only " + std::to_string(nodes.size()) + " nodes");
  if (edges.size() + 1 != nodes.size())
    fail(obj + ": " + std::to_string(edges.size()) + " edges for " + std::to_string(nodes.size()) + " nodes");
  SkeletonGraph graph(nodes.size());
  for (const auto& [a, b] : edges) {
    if (a < 0 || b < 0 || a >= static_cast<long>(nodes.size()) || b >= static_cast<long>(nodes.size()))
      fail(obj + ": an edge names a node that does not exist");
    boost::add_edge(static_cast<NodeId>(a), static_cast<NodeId>(b), graph);
  }
  if (!is_tree(graph)) fail(obj + ": the edges form a cycle");  // n - 1 edges: a cycle iff not connected

  // Smoothing splines may overshoot a branch tip a little beyond the outermost point.
  Eigen::AlignedBox3d box = world_box(io::read_point_cloud(cloud_file));
  const double slack = 0.02 * box.diagonal().norm();
  box.extend(box.min() - Eigen::Vector3d::Constant(slack)).extend(box.max() + Eigen::Vector3d::Constant(slack));
  for (const auto& p : nodes)
    if (!box.contains(p)) fail(obj + ": a node lies outside the cloud's bounding box (+2% of its diagonal)");

  // Quality from an ASCII PLY saved with -m vq sa.
  std::ifstream q(ply);
  if (!q) fail("cannot read " + ply);
  constexpr std::size_t none = static_cast<std::size_t>(-1);
  std::size_t count = 0, properties = 0, quality = none;
  std::string element;
  for (std::string line; std::getline(q, line) && line != "end_header";) {
    std::istringstream words(line);
    std::string a, b, c;
    words >> a >> b >> c;
    if (a == "element") {
      element = b;
      if (b == "vertex") count = std::stoul(c);
    } else if (a == "property" && element == "vertex") {
      if (c == "quality") quality = properties;
      ++properties;
    }
  }
  if (count != nodes.size()) fail(ply + ": " + std::to_string(count) + " vertices, the OBJ has " + std::to_string(nodes.size()));
  if (quality == none) fail(ply + ": no quality property");
  for (std::size_t i = 0; i < count; ++i) {
    std::vector<double> row(properties);
    for (auto& value : row) q >> value;
    if (!q) fail(ply + ": truncated");
    if (!(row[quality] > 0.0)) fail(ply + ": node " + std::to_string(i) + " has radius " + std::to_string(row[quality]));
  }
  std::cout << "skeleton: " << nodes.size() << " nodes, a tree, radii positive\n";
  return 0;
}

int check_mesh(const std::string& file, const std::string& cloud_file) {
  const modeling::TreeMesh mesh = io::read_mesh(file);
  const modeling::MeshCheck check = modeling::check_mesh(mesh, true);
  if (!check.ok()) fail(file + ": " + check.problem());
  Eigen::AlignedBox3d box;
  for (const auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    box.extend(Eigen::Vector3d(p[0], p[1], p[2]));
  }
  const Eigen::AlignedBox3d cloud = world_box(io::read_point_cloud(cloud_file));
  // The mesh spans the tree: its extent is close to the cloud's on every axis (twigs and noise points
  // beyond the outermost branch tips make it a little smaller), and it stays inside the box but for
  // the branch radius.
  for (int a = 0; a < 3; ++a) {
    const double ratio = box.sizes()[a] / cloud.sizes()[a];
    std::cout << "axis " << a << ": mesh extent / cloud extent = " << ratio << '\n';
    if (ratio < 0.75 || ratio > 1.1) fail(file + ": the mesh's extent differs from the cloud's");
  }
  const double slack = 0.05 * cloud.sizes().maxCoeff();
  if ((box.min() - cloud.min()).minCoeff() < -slack || (cloud.max() - box.max()).minCoeff() < -slack)
    fail(file + ": the mesh reaches outside the cloud's bounding box");
  std::cout << "mesh: " << check.faces << " triangles, closed, manifold, no self-intersection, volume " << check.volume
            << '\n';
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::vector<std::string> args(argv + 1, argv + argc);
    if (args.size() == 4 && args[0] == "skeleton") return check_skeleton(args[1], args[2], args[3]);
    if (args.size() == 3 && args[0] == "mesh") return check_mesh(args[1], args[2]);
    std::cerr << "usage: meshlab_check skeleton SKELETON.obj QUALITY.ply CLOUD | mesh MESH CLOUD\n";
    return 2;
  } catch (const std::exception& e) {
    fail(e.what());
  }
}
