#include "formats.h"

#include <charconv>

namespace treeskel::io::detail {

void append_number(std::string& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

void append_point_line(std::string& out, const PointCloud& cloud, std::size_t i) {
  const Eigen::Vector3d p = cloud.positions[i] + cloud.offset;
  for (int a = 0; a < 3; ++a) {
    if (a) out += ' ';
    append_number(out, p[a]);
  }
  if (cloud.has_normals())
    for (int a = 0; a < 3; ++a) {
      out += ' ';
      append_number(out, cloud.normals[i][a]);
    }
  if (cloud.has_colors())
    for (int a = 0; a < 3; ++a) out += ' ' + std::to_string(cloud.colors[i][a]);
  out += '\n';
}

bool parse_number(std::string_view token, double& value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  if (token.empty()) return false;
  const auto result = std::from_chars(token.data(), token.data() + token.size(), value);
  return result.ec == std::errc() && result.ptr == token.data() + token.size();
}

}  // namespace treeskel::io::detail
