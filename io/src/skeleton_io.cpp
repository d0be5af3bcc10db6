#include "treeskel/io/skeleton_io.h"

#include "formats.h"
#include "treeskel/error.h"
#include "treeskel/io/atomic_file.h"

#include <nlohmann/json.hpp>

#include <ostream>
#include <sstream>

namespace treeskel::io {

namespace {

using detail::append_number;

Eigen::Vector3d world(const Skeleton& s, NodeId v) { return s.graph[v].position + s.offset; }

void write_ply(std::ostream& out, const Skeleton& s) {
  std::string text = "ply\nformat ascii 1.0\ncomment written by treeskel\ncomment root " + std::to_string(s.root) +
                     "\nelement vertex " + std::to_string(s.node_count()) +
                     "\nproperty double x\nproperty double y\nproperty double z\nproperty double radius\n"
                     "element edge " + std::to_string(s.edge_count()) +
                     "\nproperty int vertex1\nproperty int vertex2\nend_header\n";
  for (NodeId v = 0; v < s.node_count(); ++v) {
    const Eigen::Vector3d p = world(s, v);
    for (int a = 0; a < 3; ++a) {
      append_number(text, p[a]);
      text += ' ';
    }
    append_number(text, s.graph[v].radius);
    text += '\n';
  }
  for (auto e : boost::make_iterator_range(boost::edges(s.graph)))
    text += std::to_string(boost::source(e, s.graph)) + ' ' + std::to_string(boost::target(e, s.graph)) + '\n';
  out << text;
}

void write_obj(std::ostream& out, const Skeleton& s) {
  std::string text = "# treeskel skeleton: " + std::to_string(s.node_count()) + " nodes, root " +
                     std::to_string(s.root + 1) + "\n";
  for (NodeId v = 0; v < s.node_count(); ++v) {
    const Eigen::Vector3d p = world(s, v);
    text += 'v';
    for (int a = 0; a < 3; ++a) {
      text += ' ';
      append_number(text, p[a]);
    }
    text += '\n';
  }
  for (auto e : boost::make_iterator_range(boost::edges(s.graph)))
    text += "l " + std::to_string(boost::source(e, s.graph) + 1) + ' ' + std::to_string(boost::target(e, s.graph) + 1) + '\n';
  out << text;
}

Skeleton from_json(const std::string& data, const std::string& name) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(data);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(name + ": not valid JSON: " + e.what());
  }
  Skeleton s;
  try {
    for (const auto& node : j.at("nodes")) {
      SkeletonNode n;
      const auto& p = node.at("position");
      n.position = {p.at(0).get<double>(), p.at(1).get<double>(), p.at(2).get<double>()};
      n.radius = node.value("radius", 0.0);
      add_node(s, n);
    }
    for (const auto& e : j.at("edges")) {
      const auto a = e.at(0).get<std::size_t>(), b = e.at(1).get<std::size_t>();
      if (a >= s.node_count() || b >= s.node_count())
        throw InputError(name + ": edge " + std::to_string(a) + "-" + std::to_string(b) + " names a node that does not exist");
      boost::add_edge(a, b, s.graph);
    }
    s.root = j.value("root", std::size_t{0});
  } catch (const nlohmann::json::exception& e) {
    throw InputError(name + ": not a treeskel skeleton: " + e.what());
  }
  return s;
}

Skeleton from_ply(const std::string& data, const std::string& name) {
  std::istringstream in(data);
  std::string line;
  std::getline(in, line);
  if (line.rfind("ply", 0) != 0) throw InputError(name + ": not a PLY file");
  std::size_t vertices = 0, edges = 0;
  bool root_given = false;
  std::size_t root = 0;
  std::vector<std::string> vertex_props, edge_props;
  std::vector<std::string>* current = nullptr;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string w;
    words >> w;
    if (w == "end_header") break;
    if (w == "format") {
      words >> w;
      if (w != "ascii") throw InputError(name + ": only ascii skeleton PLY files are read (this one is " + w + ")");
    } else if (w == "comment") {
      words >> w;
      if (w == "root" && (words >> root)) root_given = true;
    } else if (w == "element") {
      std::size_t count = 0;
      words >> w >> count;
      if (w == "vertex") vertices = count, current = &vertex_props;
      else if (w == "edge") edges = count, current = &edge_props;
      else current = nullptr;
    } else if (w == "property" && current) {
      std::string type, prop;
      words >> type >> prop;
      current->push_back(prop);
    }
  }
  auto column = [&](const std::vector<std::string>& props, const char* want) -> int {
    for (std::size_t i = 0; i < props.size(); ++i)
      if (props[i] == want) return static_cast<int>(i);
    return -1;
  };
  const int cx = column(vertex_props, "x"), cy = column(vertex_props, "y"), cz = column(vertex_props, "z"),
            cr = column(vertex_props, "radius");
  const int c1 = column(edge_props, "vertex1"), c2 = column(edge_props, "vertex2");
  if (cx < 0 || cy < 0 || cz < 0) throw InputError(name + ": the skeleton PLY has no x, y, z vertex properties");
  if (edges > 0 && (c1 < 0 || c2 < 0)) throw InputError(name + ": the skeleton PLY edges lack vertex1/vertex2");
  Skeleton s;
  std::vector<double> values;
  auto read_row = [&](std::size_t width, const char* what, std::size_t k) {
    values.assign(width, 0.0);
    for (auto& v : values)
      if (!(in >> v)) throw InputError(name + ": the data ends inside " + what + " " + std::to_string(k));
  };
  for (std::size_t k = 0; k < vertices; ++k) {
    read_row(vertex_props.size(), "vertex", k);
    SkeletonNode n;
    n.position = {values[cx], values[cy], values[cz]};
    if (cr >= 0) n.radius = values[cr];
    add_node(s, n);
  }
  for (std::size_t k = 0; k < edges; ++k) {
    read_row(edge_props.size(), "edge", k);
    const auto a = static_cast<std::size_t>(values[c1]), b = static_cast<std::size_t>(values[c2]);
    if (a >= vertices || b >= vertices) throw InputError(name + ": edge " + std::to_string(k) + " names a missing vertex");
    boost::add_edge(a, b, s.graph);
  }
  if (root_given) s.root = root;
  else if (vertices > 0) {
    for (NodeId v = 1; v < vertices; ++v)
      if (s.graph[v].position.z() < s.graph[s.root].position.z()) s.root = v;
  }
  return s;
}

}  // namespace

std::string skeleton_to_json(const Skeleton& s) {
  nlohmann::ordered_json j;
  j["format"] = "treeskel skeleton";
  j["version"] = 1;
  j["root"] = s.root;
  j["node_count"] = s.node_count();
  j["branch_points"] = count_branch_points(s.graph);
  j["endpoints"] = count_endpoints(s.graph);
  auto& nodes = j["nodes"] = nlohmann::ordered_json::array();
  for (NodeId v = 0; v < s.node_count(); ++v) {
    const Eigen::Vector3d p = world(s, v);
    nodes.push_back({{"id", v}, {"position", {p.x(), p.y(), p.z()}}, {"radius", s.graph[v].radius},
                     {"points", s.graph[v].points.size()}});
  }
  auto& edges = j["edges"] = nlohmann::ordered_json::array();
  for (auto e : boost::make_iterator_range(boost::edges(s.graph)))
    edges.push_back({boost::source(e, s.graph), boost::target(e, s.graph)});
  return j.dump(1) + "\n";
}

bool is_skeleton_extension(const std::filesystem::path& path) {
  const std::string ext = extension_of(path);
  return ext == "ply" || ext == "obj" || ext == "json";
}

void write_skeleton(const std::filesystem::path& path, const Skeleton& skeleton) {
  const std::string ext = extension_of(path);
  if (!is_skeleton_extension(path))
    throw Error(path.string() + ": unknown skeleton extension '." + ext + "'; treeskel writes skeletons as .ply, .obj or .json");
  write_atomically(path, [&](std::ostream& out) {
    if (ext == "ply") write_ply(out, skeleton);
    else if (ext == "obj") write_obj(out, skeleton);
    else out << skeleton_to_json(skeleton);
  });
}

Skeleton read_skeleton(const std::filesystem::path& path) {
  const std::string ext = extension_of(path);
  if (ext != "ply" && ext != "json")
    throw InputError(path.string() + ": unknown skeleton extension '." + ext + "'; treeskel reads .ply and .json skeletons");
  const std::string data = read_whole_file(path);
  if (data.empty()) throw InputError(path.string() + ": the file is empty");
  Skeleton s = ext == "json" ? from_json(data, path.string()) : from_ply(data, path.string());
  if (s.node_count() == 0) throw InputError(path.string() + ": the skeleton has no node");
  if (s.root >= s.node_count()) throw InputError(path.string() + ": the root is not a node");
  return s;
}

}  // namespace treeskel::io
