// PLY point clouds, read with the PLY reader of ply_format.h (ascii and binary, any numeric property
// types). The vertex element must have x, y and z; nx ny nz and red green blue are read when present;
// other elements (faces, edges) are skipped.
#include "formats.h"
#include "ply_format.h"

#include "treeskel/error.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <ostream>
#include <vector>

namespace treeskel::io::detail {

namespace {

/// Indices of the properties the cloud uses in the vertex element (-1 = absent).
struct VertexLayout {
  int at[9];  // x y z nx ny nz red green blue
  PlyType color_type = PlyType::uint8;
};

VertexLayout layout_of(const PlyElement& vertex, const std::string& name) {
  static const char* wanted[9][2] = {{"x", nullptr},  {"y", nullptr},     {"z", nullptr},
                                     {"nx", "normal_x"}, {"ny", "normal_y"}, {"nz", "normal_z"},
                                     {"red", "r"},     {"green", "g"},     {"blue", "b"}};
  VertexLayout layout;
  std::fill(std::begin(layout.at), std::end(layout.at), -1);
  for (int a = 0; a < 9; ++a)
    for (const char* w : wanted[a])
      if (w && layout.at[a] < 0) layout.at[a] = vertex.find(w);
  if (layout.at[0] < 0 || layout.at[1] < 0 || layout.at[2] < 0)
    throw InputError(name + ": the PLY vertex element has no x, y and z properties");
  if (layout.at[3] < 0 || layout.at[4] < 0 || layout.at[5] < 0) layout.at[3] = -1;
  if (layout.at[6] < 0 || layout.at[7] < 0 || layout.at[8] < 0) layout.at[6] = -1;
  if (layout.at[6] >= 0) layout.color_type = vertex.properties[layout.at[6]].type;
  return layout;
}

std::uint8_t to_color(double v, PlyType t) {
  if (t == PlyType::float32 || t == PlyType::float64) v *= 255.0;
  else if (t == PlyType::uint16) v /= 257.0;
  if (!(v >= 0.0)) return 0;  // NaN too
  return static_cast<std::uint8_t>(std::min(std::lround(std::min(v, 255.0)), 255L));
}

}  // namespace

PointCloud read_ply(std::string_view data, const std::string& name) {
  const PlyHeader header = parse_ply_header(data, name);
  const PlyElement* vertex = header.find("vertex");
  if (!vertex) throw InputError(name + ": the PLY file has no vertex element");
  const VertexLayout layout = layout_of(*vertex, name);

  PointCloud cloud;
  cloud.positions.reserve(static_cast<std::size_t>(vertex->count));  // bounded by the file's size
  std::vector<bool> wanted(header.elements.size(), false);
  wanted[static_cast<std::size_t>(vertex - header.elements.data())] = true;
  read_ply_body(data, header, wanted, [&](std::size_t, std::uint64_t k, const double* values) {
    const Eigen::Vector3d p(values[layout.at[0]], values[layout.at[1]], values[layout.at[2]]);
    if (!p.allFinite())
      throw InputError(name + ": vertex " + std::to_string(k) + " has a coordinate that is not a finite number");
    cloud.positions.push_back(p);
    if (layout.at[3] >= 0)
      cloud.normals.emplace_back(float(values[layout.at[3]]), float(values[layout.at[4]]), float(values[layout.at[5]]));
    if (layout.at[6] >= 0)
      cloud.colors.push_back({to_color(values[layout.at[6]], layout.color_type),
                              to_color(values[layout.at[7]], layout.color_type),
                              to_color(values[layout.at[8]], layout.color_type)});
  }, name);
  if (cloud.empty()) throw InputError(name + ": holds no points");
  return cloud;
}

void write_ply(std::ostream& out, const PointCloud& cloud, bool binary, const std::vector<PointField>& fields) {
  std::string header = "ply\nformat ";
  header += binary ? "binary_little_endian 1.0\n" : "ascii 1.0\n";
  header += "comment written by treeskel\nelement vertex " + std::to_string(cloud.size()) + "\n";
  header += "property double x\nproperty double y\nproperty double z\n";
  if (cloud.has_normals()) header += "property float nx\nproperty float ny\nproperty float nz\n";
  if (cloud.has_colors()) header += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  for (const auto& f : fields)
    header += std::string("property ") +
              (f.type == PointField::Type::uint8 ? "uchar " : f.type == PointField::Type::uint32 ? "uint " : "float ") +
              f.name + "\n";
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
      for (const auto& f : fields) {
        if (f.type == PointField::Type::uint8) {
          const auto v = static_cast<std::uint8_t>(f.values[i]);
          put(&v, 1);
        } else if (f.type == PointField::Type::uint32) {
          const auto v = static_cast<std::uint32_t>(f.values[i]);
          put(&v, 4);
        } else {
          const auto v = static_cast<float>(f.values[i]);
          put(&v, 4);
        }
      }
    } else {
      append_point_line(buffer, cloud, i);
      if (!fields.empty()) {
        buffer.pop_back();  // the line's end
        for (const auto& f : fields) {
          buffer += ' ';
          append_number(buffer, f.type == PointField::Type::float32 ? static_cast<double>(static_cast<float>(f.values[i])) : f.values[i]);
        }
        buffer += '\n';
      }
    }
    if (buffer.size() > (1u << 20)) {
      out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
      buffer.clear();
    }
  }
  out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
}

}  // namespace treeskel::io::detail
