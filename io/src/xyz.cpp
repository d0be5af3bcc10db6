// Plain-text clouds: .xyz .txt .asc .csv and .pts. One point a line, numbers separated by white space,
// commas or semicolons; '#' starts a comment; CRLF line ends are accepted. An optional first line of
// column names (x y z, nx ny nz, r g b / red green blue) picks the columns; without it the first three
// numbers are x y z and the rest are ignored. A line of one whole number (the point count that
// Leica's and CloudCompare's .pts put before each scan's points) is passed over.
#include "formats.h"

#include "treeskel/error.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <ostream>
#include <vector>

namespace treeskel::io::detail {

namespace {

constexpr std::size_t kLongestLine = 1 << 16;

bool is_separator(char c) { return c == ' ' || c == '\t' || c == ',' || c == ';' || c == '\r' || c == '\v' || c == '\f'; }

void split(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_separator(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_separator(line[i])) ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
}

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

/// Column of each attribute: x y z nx ny nz r g b (-1 = absent).
using Columns = std::array<int, 9>;

bool header_columns(const std::vector<std::string_view>& tokens, Columns& columns) {
  columns.fill(-1);
  static const std::array<std::vector<const char*>, 9> names{{{"x", "//x"}, {"y"}, {"z"}, {"nx", "normal_x"},
                                                              {"ny", "normal_y"}, {"nz", "normal_z"},
                                                              {"r", "red"}, {"g", "green"}, {"b", "blue"}}};
  for (std::size_t t = 0; t < tokens.size(); ++t) {
    const std::string name = lower(tokens[t]);
    for (std::size_t a = 0; a < names.size(); ++a)
      for (const char* candidate : names[a])
        if (name == candidate && columns[a] < 0) columns[a] = static_cast<int>(t);
  }
  return columns[0] >= 0 && columns[1] >= 0 && columns[2] >= 0;
}

}  // namespace

PointCloud read_xyz(std::string_view all, const std::string& name) {
  PointCloud cloud;
  Columns columns{0, 1, 2, -1, -1, -1, -1, -1, -1};
  bool seen_content = false;
  std::vector<std::string_view> tokens;
  std::size_t line_number = 0;
  std::size_t pos = 0;
  while (pos < all.size()) {
    // A line is searched for no further than the longest line a point cloud has, so a huge file of
    // another kind is refused at its first line.
    const std::string_view rest = all.substr(pos, std::min(all.size() - pos, kLongestLine + 1));
    std::size_t end = rest.find('\n');
    ++line_number;
    if (end == std::string_view::npos && rest.size() > kLongestLine)
      throw InputError(name + ": line " + std::to_string(line_number) +
                       " is longer than 64 KiB; expected text with one point a line");
    if (end == std::string_view::npos) end = rest.size();
    std::string_view line = rest.substr(0, end);
    pos += end + 1;
    if (const auto nul = line.find('\0'); nul != std::string_view::npos)
      throw InputError(name + ": holds binary data (a NUL byte at byte " + std::to_string(pos - end - 1 + nul) +
                       "); expected text with one point a line");
    if (const auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    split(line, tokens);
    if (tokens.empty()) continue;
    double value = 0.0;
    if (!seen_content) {
      seen_content = true;
      const bool all_words = std::none_of(tokens.begin(), tokens.end(), [&](auto t) { return parse_number(t, value); });
      if (all_words) {
        if (!header_columns(tokens, columns))
          throw InputError(name + ": line " + std::to_string(line_number) +
                           ": a header line must name the columns x, y and z");
        if (columns[3] >= 0 && (columns[4] < 0 || columns[5] < 0)) columns[3] = -1;
        if (columns[6] >= 0 && (columns[7] < 0 || columns[8] < 0)) columns[6] = -1;
        continue;
      }
    }
    // Leica's and CloudCompare's .pts put the number of points of each scan on a line of its own.
    if (tokens.size() == 1 && !tokens[0].empty() &&
        std::all_of(tokens[0].begin(), tokens[0].end(), [](char c) { return c >= '0' && c <= '9'; }))
      continue;
    const int needed = *std::max_element(columns.begin(), columns.end()) + 1;
    if (static_cast<int>(tokens.size()) < std::max(needed, 3))
      throw InputError(name + ": line " + std::to_string(line_number) + ": expected at least " +
                       std::to_string(std::max(needed, 3)) + " numbers, found " + std::to_string(tokens.size()));
    double v[9];
    for (int a = 0; a < 9; ++a) {
      if (columns[a] < 0) continue;
      const auto token = tokens[columns[a]];
      if (!parse_number(token, v[a]))
        throw InputError(name + ": line " + std::to_string(line_number) + ": '" + std::string(token) +
                         "' is not a number");
      if (!std::isfinite(v[a]))
        throw InputError(name + ": line " + std::to_string(line_number) + ": '" + std::string(token) +
                         "' is not a finite number");
    }
    cloud.positions.emplace_back(v[0], v[1], v[2]);
    if (columns[3] >= 0) cloud.normals.emplace_back(float(v[3]), float(v[4]), float(v[5]));
    if (columns[6] >= 0) {
      std::array<std::uint8_t, 3> rgb{};
      for (int a = 0; a < 3; ++a) rgb[a] = static_cast<std::uint8_t>(std::clamp(std::lround(v[6 + a]), 0L, 255L));
      cloud.colors.push_back(rgb);
    }
  }
  if (cloud.empty()) throw InputError(name + ": holds no points");
  return cloud;
}

void write_xyz(std::ostream& out, const PointCloud& cloud) {
  std::string header = "x y z";
  if (cloud.has_normals()) header += " nx ny nz";
  if (cloud.has_colors()) header += " red green blue";
  out << header << '\n';
  std::string buffer;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    append_point_line(buffer, cloud, i);
    if (buffer.size() > (1u << 20)) {
      out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
      buffer.clear();
    }
  }
  out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
}

}  // namespace treeskel::io::detail
