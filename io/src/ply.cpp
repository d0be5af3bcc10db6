// PLY point clouds: ascii, binary_little_endian and binary_big_endian, any numeric property types.
// The vertex element must have x, y and z; nx ny nz and red green blue are read when present; other
// elements (faces, edges) are skipped.
#include "formats.h"

#include "treeskel/error.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <ostream>
#include <vector>

namespace treeskel::io::detail {

namespace {

enum class Type { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

std::size_t size_of(Type t) {
  switch (t) {
    case Type::int8: case Type::uint8: return 1;
    case Type::int16: case Type::uint16: return 2;
    case Type::int32: case Type::uint32: case Type::float32: return 4;
    case Type::float64: return 8;
  }
  return 0;
}

bool parse_type(const std::string& s, Type& t) {
  static const std::pair<const char*, Type> table[] = {
      {"char", Type::int8},     {"int8", Type::int8},       {"uchar", Type::uint8},    {"uint8", Type::uint8},
      {"short", Type::int16},   {"int16", Type::int16},     {"ushort", Type::uint16},  {"uint16", Type::uint16},
      {"int", Type::int32},     {"int32", Type::int32},     {"uint", Type::uint32},    {"uint32", Type::uint32},
      {"float", Type::float32}, {"float32", Type::float32}, {"double", Type::float64}, {"float64", Type::float64}};
  for (const auto& [name, type] : table)
    if (s == name) {
      t = type;
      return true;
    }
  return false;
}

struct Property {
  std::string name;
  Type type = Type::float32;
  bool list = false;
  Type count_type = Type::uint8;
};

struct Element {
  std::string name;
  std::size_t count = 0;
  std::vector<Property> properties;
};

enum class Format { ascii, little, big };

double read_binary(const char* p, Type t, bool swap) {
  unsigned char b[8];
  const std::size_t n = size_of(t);
  std::memcpy(b, p, n);
  if (swap) std::reverse(b, b + n);
  switch (t) {
    case Type::int8: { std::int8_t v; std::memcpy(&v, b, 1); return v; }
    case Type::uint8: return b[0];
    case Type::int16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
    case Type::uint16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
    case Type::int32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
    case Type::uint32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
    case Type::float32: { float v; std::memcpy(&v, b, 4); return v; }
    case Type::float64: { double v; std::memcpy(&v, b, 8); return v; }
  }
  return 0.0;
}

bool host_is_little() {
  const std::uint16_t one = 1;
  unsigned char c;
  std::memcpy(&c, &one, 1);
  return c == 1;
}

/// Indices of the properties the cloud uses in the vertex element (-1 = absent).
struct VertexLayout {
  int at[9];  // x y z nx ny nz red green blue
  Type color_type = Type::uint8;
};

VertexLayout layout_of(const Element& vertex, const std::string& name) {
  static const char* wanted[9][2] = {{"x", nullptr},  {"y", nullptr},     {"z", nullptr},
                                     {"nx", "normal_x"}, {"ny", "normal_y"}, {"nz", "normal_z"},
                                     {"red", "r"},     {"green", "g"},     {"blue", "b"}};
  VertexLayout layout;
  std::fill(std::begin(layout.at), std::end(layout.at), -1);
  for (std::size_t p = 0; p < vertex.properties.size(); ++p)
    for (int a = 0; a < 9; ++a)
      for (const char* w : wanted[a])
        if (w && vertex.properties[p].name == w && !vertex.properties[p].list && layout.at[a] < 0)
          layout.at[a] = static_cast<int>(p);
  if (layout.at[0] < 0 || layout.at[1] < 0 || layout.at[2] < 0)
    throw InputError(name + ": the PLY vertex element has no x, y and z properties");
  if (layout.at[3] < 0 || layout.at[4] < 0 || layout.at[5] < 0) layout.at[3] = -1;
  if (layout.at[6] < 0 || layout.at[7] < 0 || layout.at[8] < 0) layout.at[6] = -1;
  if (layout.at[6] >= 0) layout.color_type = vertex.properties[layout.at[6]].type;
  return layout;
}

std::uint8_t to_color(double v, Type t) {
  if (t == Type::float32 || t == Type::float64) v *= 255.0;
  else if (t == Type::uint16) v /= 257.0;
  return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
}

void add_vertex(PointCloud& cloud, const VertexLayout& layout, const double* values, std::size_t index,
                const std::string& where) {
  const Eigen::Vector3d p(values[layout.at[0]], values[layout.at[1]], values[layout.at[2]]);
  if (!p.allFinite())
    throw InputError(where + ": vertex " + std::to_string(index) + " has a coordinate that is not a finite number");
  cloud.positions.push_back(p);
  if (layout.at[3] >= 0)
    cloud.normals.emplace_back(float(values[layout.at[3]]), float(values[layout.at[4]]), float(values[layout.at[5]]));
  if (layout.at[6] >= 0)
    cloud.colors.push_back({to_color(values[layout.at[6]], layout.color_type), to_color(values[layout.at[7]], layout.color_type),
                            to_color(values[layout.at[8]], layout.color_type)});
}

}  // namespace

PointCloud read_ply(const std::string& data, const std::string& name) {
  // --- header
  std::size_t pos = 0;
  std::size_t line_number = 0;
  auto next_line = [&](std::string& line) -> bool {
    if (pos >= data.size()) return false;
    std::size_t end = data.find('\n', pos);
    if (end == std::string::npos) end = data.size();
    line.assign(data, pos, end - pos);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    pos = std::min(end + 1, data.size() + 1);
    ++line_number;
    return true;
  };
  std::string line;
  if (!next_line(line) || line != "ply") throw InputError(name + ": not a PLY file (it does not start with 'ply')");
  Format format = Format::ascii;
  bool have_format = false, ended = false;
  std::vector<Element> elements;
  while (next_line(line)) {
    std::vector<std::string> words;
    for (std::size_t i = 0; i < line.size();) {
      while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
      const std::size_t s = i;
      while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
      if (i > s) words.push_back(line.substr(s, i - s));
    }
    if (words.empty() || words[0] == "comment" || words[0] == "obj_info") continue;
    const std::string where = name + ": line " + std::to_string(line_number);
    if (words[0] == "end_header") {
      ended = true;
      break;
    }
    if (words[0] == "format") {
      if (words.size() < 2) throw InputError(where + ": PLY format line without a format");
      if (words[1] == "ascii") format = Format::ascii;
      else if (words[1] == "binary_little_endian") format = Format::little;
      else if (words[1] == "binary_big_endian") format = Format::big;
      else throw InputError(where + ": unknown PLY format '" + words[1] + "'");
      have_format = true;
    } else if (words[0] == "element") {
      double count = 0;
      if (words.size() != 3 || !parse_number(words[2], count) || count < 0 || count != std::floor(count))
        throw InputError(where + ": malformed element line '" + line + "'");
      elements.push_back({words[1], static_cast<std::size_t>(count), {}});
    } else if (words[0] == "property") {
      if (elements.empty()) throw InputError(where + ": property before any element");
      Property p;
      if (words.size() == 5 && words[1] == "list") {
        p.list = true;
        if (!parse_type(words[2], p.count_type) || !parse_type(words[3], p.type))
          throw InputError(where + ": unknown PLY type in '" + line + "'");
        p.name = words[4];
      } else if (words.size() == 3) {
        if (!parse_type(words[1], p.type)) throw InputError(where + ": unknown PLY type '" + words[1] + "'");
        p.name = words[2];
      } else {
        throw InputError(where + ": malformed property line '" + line + "'");
      }
      elements.back().properties.push_back(p);
    } else {
      throw InputError(where + ": unexpected PLY header line '" + line + "'");
    }
  }
  if (!ended) throw InputError(name + ": the PLY header has no end_header line");
  if (!have_format) throw InputError(name + ": the PLY header has no format line");
  const auto vertex_it = std::find_if(elements.begin(), elements.end(), [](const Element& e) { return e.name == "vertex"; });
  if (vertex_it == elements.end()) throw InputError(name + ": the PLY file has no vertex element");
  const VertexLayout layout = layout_of(*vertex_it, name);

  PointCloud cloud;
  cloud.positions.reserve(vertex_it->count);
  std::vector<double> values;

  if (format == Format::ascii) {
    std::size_t i = pos;
    auto next_token = [&](std::string_view& token) -> bool {
      while (i < data.size() && std::isspace(static_cast<unsigned char>(data[i]))) {
        if (data[i] == '\n') ++line_number;
        ++i;
      }
      if (i >= data.size()) return false;
      const std::size_t s = i;
      while (i < data.size() && !std::isspace(static_cast<unsigned char>(data[i]))) ++i;
      token = std::string_view(data).substr(s, i - s);
      return true;
    };
    auto number = [&](const Element& e, std::size_t k) -> double {
      std::string_view token;
      if (!next_token(token))
        throw InputError(name + ": line " + std::to_string(line_number + 1) + ": the data ends after " +
                         std::to_string(k) + " of the " + std::to_string(e.count) + " " + e.name +
                         " elements the header declares");
      double v = 0;
      if (!parse_number(token, v))
        throw InputError(name + ": line " + std::to_string(line_number + 1) + ": '" + std::string(token) +
                         "' is not a number");
      return v;
    };
    for (const auto& e : elements) {
      const bool is_vertex = &e == &*vertex_it;
      for (std::size_t k = 0; k < e.count; ++k) {
        values.assign(e.properties.size(), 0.0);
        for (std::size_t p = 0; p < e.properties.size(); ++p) {
          if (e.properties[p].list) {
            const double n = number(e, k);
            if (n < 0 || n != std::floor(n))
              throw InputError(name + ": line " + std::to_string(line_number + 1) + ": bad list length");
            for (std::size_t j = 0; j < static_cast<std::size_t>(n); ++j) number(e, k);
          } else {
            values[p] = number(e, k);
          }
        }
        if (is_vertex) add_vertex(cloud, layout, values.data(), k, name + ": line " + std::to_string(line_number + 1));
      }
    }
    std::string_view extra;
    if (next_token(extra))
      throw InputError(name + ": line " + std::to_string(line_number + 1) +
                       ": more data than the header declares (starting with '" + std::string(extra) + "')");
  } else {
    const bool swap = (format == Format::little) != host_is_little();
    std::size_t at = pos;
    for (const auto& e : elements) {
      const bool is_vertex = &e == &*vertex_it;
      const bool fixed = std::none_of(e.properties.begin(), e.properties.end(), [](const Property& p) { return p.list; });
      std::size_t stride = 0;
      for (const auto& p : e.properties) stride += size_of(p.type);
      if (fixed) {
        const std::size_t available = data.size() - at;
        if (stride > 0 && available / stride < e.count)
          throw InputError(name + ": truncated: the header declares " + std::to_string(e.count) + " " + e.name +
                           " elements (" + std::to_string(e.count * stride) + " bytes from byte " + std::to_string(at) +
                           ") but only " + std::to_string(available) + " bytes follow");
      }
      for (std::size_t k = 0; k < e.count; ++k) {
        values.assign(e.properties.size(), 0.0);
        for (std::size_t p = 0; p < e.properties.size(); ++p) {
          const auto& prop = e.properties[p];
          auto need = [&](std::size_t bytes) {
            if (data.size() - at < bytes)
              throw InputError(name + ": truncated at byte " + std::to_string(data.size()) + ", inside " + e.name +
                               " element " + std::to_string(k) + " of " + std::to_string(e.count));
          };
          if (prop.list) {
            need(size_of(prop.count_type));
            const double n = read_binary(data.data() + at, prop.count_type, swap);
            at += size_of(prop.count_type);
            if (n < 0) throw InputError(name + ": byte " + std::to_string(at) + ": negative list length");
            const std::size_t bytes = static_cast<std::size_t>(n) * size_of(prop.type);
            need(bytes);
            at += bytes;
          } else {
            need(size_of(prop.type));
            values[p] = read_binary(data.data() + at, prop.type, swap);
            at += size_of(prop.type);
          }
        }
        if (is_vertex) add_vertex(cloud, layout, values.data(), k, name);
      }
    }
    if (at != data.size())
      throw InputError(name + ": byte " + std::to_string(at) + ": " + std::to_string(data.size() - at) +
                       " bytes follow the last element the header declares (does the header count the points right?)");
  }
  if (cloud.empty()) throw InputError(name + ": holds no points");
  return cloud;
}

void write_ply(std::ostream& out, const PointCloud& cloud, bool binary) {
  std::string header = "ply\nformat ";
  header += binary ? "binary_little_endian 1.0\n" : "ascii 1.0\n";
  header += "comment written by treeskel\nelement vertex " + std::to_string(cloud.size()) + "\n";
  header += "property double x\nproperty double y\nproperty double z\n";
  if (cloud.has_normals()) header += "property float nx\nproperty float ny\nproperty float nz\n";
  if (cloud.has_colors()) header += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  header += "end_header\n";
  out << header;
  std::string buffer;
  const bool swap = !host_is_little();
  auto put = [&](const void* p, std::size_t n) {
    const auto* b = static_cast<const char*>(p);
    if (swap) buffer.append(std::string(b, n).rbegin(), std::string(b, n).rend());
    else buffer.append(b, n);
  };
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (binary) {
      const Eigen::Vector3d p = cloud.positions[i] + cloud.offset;
      for (int a = 0; a < 3; ++a) put(&p[a], 8);
      if (cloud.has_normals())
        for (int a = 0; a < 3; ++a) put(&cloud.normals[i][a], 4);
      if (cloud.has_colors()) buffer.append(reinterpret_cast<const char*>(cloud.colors[i].data()), 3);
    } else {
      append_point_line(buffer, cloud, i);
    }
    if (buffer.size() > (1u << 20)) {
      out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
      buffer.clear();
    }
  }
  out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
}

}  // namespace treeskel::io::detail
