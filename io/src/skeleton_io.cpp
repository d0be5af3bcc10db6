#include "treeskel/io/skeleton_io.h"

#include "formats.h"
#include "input_file.h"
#include "ply_format.h"
#include "treeskel/error.h"
#include "treeskel/io/atomic_file.h"

#include <nlohmann/json.hpp>

#include <charconv>
#include <cmath>
#include <ostream>

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

}  // namespace

namespace detail {

namespace {

/// A node index in a JSON skeleton: a whole number not below zero. nlohmann's get<size_t> of a
/// fraction or a negative number is an out-of-range conversion, so those are refused first.
std::size_t node_index(const nlohmann::json& v, const std::string& name, const std::string& what) {
  if (!v.is_number_unsigned())
    throw InputError(name + ": " + what + " must be a node index (a whole number not below 0), not " + v.dump());
  return v.get<std::size_t>();
}

}  // namespace

Skeleton read_skeleton_json(std::string_view data, const std::string& name) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(data.begin(), data.end());
  } catch (const nlohmann::json::exception& e) {  // parse_error, and out_of_range for a number too large
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
      const auto a = node_index(e.at(0), name, "an edge's end"), b = node_index(e.at(1), name, "an edge's end");
      if (a >= s.node_count() || b >= s.node_count())
        throw InputError(name + ": edge " + std::to_string(a) + "-" + std::to_string(b) + " names a node that does not exist");
      boost::add_edge(a, b, s.graph);
    }
    s.root = j.contains("root") ? node_index(j["root"], name, "the root") : 0;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(name + ": not a treeskel skeleton: " + e.what());
  }
  return s;
}

/// The vertex and edge elements of a skeleton PLY, or nullptrs.
struct SkeletonElements {
  const detail::PlyElement* vertex = nullptr;
  const detail::PlyElement* edge = nullptr;
};

SkeletonElements skeleton_elements(const detail::PlyHeader& header) {
  SkeletonElements out;
  out.vertex = header.find("vertex");
  out.edge = header.find("edge");
  if (out.vertex && (out.vertex->find("x") < 0 || out.vertex->find("y") < 0 || out.vertex->find("z") < 0))
    out.vertex = nullptr;
  if (out.edge && (out.edge->find("vertex1") < 0 || out.edge->find("vertex2") < 0)) out.edge = nullptr;
  return out;
}

Skeleton read_skeleton_ply(std::string_view data, const std::string& name) {
  const detail::PlyHeader header = detail::parse_ply_header(data, name);
  const SkeletonElements found = skeleton_elements(header);
  if (!found.vertex) throw InputError(name + ": the skeleton PLY has no vertex element with x, y and z");
  if (header.find("edge") && !found.edge) throw InputError(name + ": the skeleton PLY's edges lack vertex1/vertex2");
  const std::size_t vertex_index = static_cast<std::size_t>(found.vertex - header.elements.data());
  const int cx = found.vertex->find("x"), cy = found.vertex->find("y"), cz = found.vertex->find("z"),
            cr = found.vertex->find("radius");
  const int c1 = found.edge ? found.edge->find("vertex1") : -1, c2 = found.edge ? found.edge->find("vertex2") : -1;
  std::vector<bool> wanted(header.elements.size(), false);
  wanted[vertex_index] = true;
  if (found.edge) wanted[static_cast<std::size_t>(found.edge - header.elements.data())] = true;

  Skeleton s;
  const std::uint64_t vertices = found.vertex->count;
  std::vector<std::pair<std::size_t, std::size_t>> edges;
  detail::read_ply_body(data, header, wanted, [&](std::size_t element, std::uint64_t k, const double* values) {
    if (element == vertex_index) {
      SkeletonNode n;
      n.position = {values[cx], values[cy], values[cz]};
      if (!n.position.allFinite())
        throw InputError(name + ": vertex " + std::to_string(k) + " has a coordinate that is not a finite number");
      if (cr >= 0) n.radius = values[cr];
      add_node(s, n);
      return;
    }
    const double a = values[c1], b = values[c2];
    if (!(a >= 0 && b >= 0 && a < static_cast<double>(vertices) && b < static_cast<double>(vertices)) ||
        a != std::floor(a) || b != std::floor(b))
      throw InputError(name + ": edge " + std::to_string(k) + " names a vertex that does not exist");
    edges.emplace_back(static_cast<std::size_t>(a), static_cast<std::size_t>(b));
  }, name);
  for (const auto& [a, b] : edges) boost::add_edge(a, b, s.graph);  // after every vertex, whatever the order

  bool root_given = false;
  for (const auto& comment : header.comments) {
    std::size_t root = 0;
    if (comment.rfind("root ", 0) == 0) {
      const auto text = std::string_view(comment).substr(5);
      const auto parsed = std::from_chars(text.data(), text.data() + text.size(), root);
      if (parsed.ec == std::errc()) {
        s.root = root;
        root_given = true;
      }
    }
  }
  if (!root_given)
    for (NodeId v = 1; v < s.node_count(); ++v)
      if (s.graph[v].position.z() < s.graph[s.root].position.z()) s.root = v;
  return s;
}

}  // namespace detail

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
  const detail::InputFile file(path);
  const std::string_view data = file.bytes();
  if (data.empty()) throw InputError(path.string() + ": the file is empty");
  Skeleton s = ext == "json" ? detail::read_skeleton_json(data, path.string()) : detail::read_skeleton_ply(data, path.string());
  if (s.node_count() == 0) throw InputError(path.string() + ": the skeleton has no node");
  if (s.root >= s.node_count()) throw InputError(path.string() + ": the root is not a node");
  return s;
}

bool looks_like_skeleton(const std::filesystem::path& path) {
  const std::string ext = extension_of(path);
  if (ext == "json") return true;
  if (ext != "ply") return false;
  const detail::InputFile file(path);
  const detail::PlyHeader header = detail::parse_ply_header(file.bytes(), path.string());
  const detail::SkeletonElements found = detail::skeleton_elements(header);
  return found.vertex && found.edge && header.find("face") == nullptr && found.edge->count > 0 &&
         2 * found.edge->count >= found.vertex->count;
}

}  // namespace treeskel::io
