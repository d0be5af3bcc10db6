#include "support/bundled.h"

#include "support/synthetic.h"
#include "treeskel/io/point_cloud_io.h"
#include "treeskel/modeling/radii.h"
#include "treeskel/pipeline.h"

#include <charconv>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace treeskel::test {

namespace {

std::string exact(double v) {
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, v).ptr);
}

double parse(const std::string& word) {
  double v = 0.0;
  const auto r = std::from_chars(word.data(), word.data() + word.size(), v);
  if (r.ec != std::errc() || r.ptr != word.data() + word.size()) throw std::runtime_error("bad number '" + word + "'");
  return v;
}

}  // namespace

Skeleton extract_bundled_skeleton(const std::string& name) {
  const std::string whole = "@whole-depths";
  const bool whole_depths = name.size() > whole.size() && name.compare(name.size() - whole.size(), whole.size(), whole) == 0;
  const PointCloud cloud = io::read_point_cloud(data_file(whole_depths ? name.substr(0, name.size() - whole.size()) : name));
  SkeletonOptions options;
  if (whole_depths) {
    // The skeleton the cases of the tests that use it were found on: whole depths, far bridging of
    // parts of ten points or more, bridging in one round (the defaults until 5 December 2026).
    options.octree.depth_steps = 1;
    options.graph.far_bridge_min_points = 10;
    options.graph.bridge_rounds = 1;
  }
  Skeleton s = extract_skeleton(cloud, options);
  // The path as the skeleton has it (no straightening of the limbs, the default since 6 December
  // 2026) where the sweep's cases were found.
  modeling::RadiusOptions radii;
  if (whole_depths) radii.stiffness = 0.0;
  modeling::fit_radii(s, &cloud, radii);
  return s;
}

Skeleton bundled_skeleton(const std::string& name) {
  if (const char* dir = std::getenv("TREESKEL_TEST_FIXTURES")) {
    const std::string path = std::string(dir) + "/" + name + ".skeleton";
    if (std::filesystem::exists(path)) return load_skeleton_fixture(path);
  }
  Skeleton s = extract_bundled_skeleton(name);
  for (NodeId v = 0; v < s.node_count(); ++v) s[v].points.clear();  // as the fixture keeps them
  return s;
}

void save_skeleton_fixture(const std::string& path, const Skeleton& s) {
  std::ostringstream out;
  out << "treeskel test skeleton 1\n"
      << exact(s.offset.x()) << ' ' << exact(s.offset.y()) << ' ' << exact(s.offset.z()) << '\n'
      << s.root << ' ' << s.node_count() << ' ' << s.edge_count() << '\n';
  for (NodeId v = 0; v < s.node_count(); ++v)
    out << exact(s[v].position.x()) << ' ' << exact(s[v].position.y()) << ' ' << exact(s[v].position.z()) << ' '
        << exact(s[v].radius) << '\n';
  for (auto e : boost::make_iterator_range(boost::edges(s.graph)))
    out << boost::source(e, s.graph) << ' ' << boost::target(e, s.graph) << '\n';
  const std::string temp = path + ".partial";
  {
    std::ofstream file(temp, std::ios::binary | std::ios::trunc);
    file << out.str();
    file.close();
    if (!file) throw std::runtime_error(path + ": cannot write");
  }
  std::filesystem::rename(temp, path);
}

Skeleton load_skeleton_fixture(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  if (!std::getline(in, line) || line != "treeskel test skeleton 1") throw std::runtime_error(path + ": not a fixture");
  std::string x, y, z, r;
  Skeleton s;
  in >> x >> y >> z;
  s.offset = {parse(x), parse(y), parse(z)};
  std::size_t root = 0, nodes = 0, edges = 0;
  in >> root >> nodes >> edges;
  for (std::size_t v = 0; v < nodes && in >> x >> y >> z >> r; ++v) {
    SkeletonNode n;
    n.position = {parse(x), parse(y), parse(z)};
    n.radius = parse(r);
    add_node(s, n);
  }
  for (std::size_t k = 0; k < edges; ++k) {
    std::size_t a = 0, b = 0;
    if (!(in >> a >> b) || a >= nodes || b >= nodes) throw std::runtime_error(path + ": bad edge");
    boost::add_edge(a, b, s.graph);
  }
  if (!in || s.node_count() != nodes || root >= nodes) throw std::runtime_error(path + ": truncated");
  s.root = root;
  return s;
}

}  // namespace treeskel::test
