#include "ply_format.h"

#include "formats.h"
#include "treeskel/error.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>

namespace treeskel::io::detail {

namespace {

constexpr std::size_t kLongestHeaderLine = 1 << 16;
constexpr std::size_t kLongestHeader = 1 << 24;

bool parse_type(std::string_view s, PlyType& t) {
  static const std::pair<const char*, PlyType> table[] = {
      {"char", PlyType::int8},       {"int8", PlyType::int8},       {"uchar", PlyType::uint8},
      {"uint8", PlyType::uint8},     {"short", PlyType::int16},     {"int16", PlyType::int16},
      {"ushort", PlyType::uint16},   {"uint16", PlyType::uint16},   {"int", PlyType::int32},
      {"int32", PlyType::int32},     {"uint", PlyType::uint32},     {"uint32", PlyType::uint32},
      {"float", PlyType::float32},   {"float32", PlyType::float32}, {"double", PlyType::float64},
      {"float64", PlyType::float64}};
  for (const auto& [type_name, type] : table)
    if (s == type_name) {
      t = type;
      return true;
    }
  return false;
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

std::vector<std::string_view> words_of(std::string_view line) {
  std::vector<std::string_view> words;
  for (std::size_t i = 0; i < line.size();) {
    while (i < line.size() && is_space(line[i])) ++i;
    const std::size_t s = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > s) words.push_back(line.substr(s, i - s));
  }
  return words;
}

double read_binary(const char* p, PlyType t, bool swap) {
  unsigned char b[8];
  const std::size_t n = size_of(t);
  std::memcpy(b, p, n);
  if (swap) std::reverse(b, b + n);
  switch (t) {
    case PlyType::int8: { std::int8_t v; std::memcpy(&v, b, 1); return v; }
    case PlyType::uint8: return b[0];
    case PlyType::int16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
    case PlyType::uint16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
    case PlyType::int32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
    case PlyType::uint32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
    case PlyType::float32: { float v; std::memcpy(&v, b, 4); return v; }
    case PlyType::float64: { double v; std::memcpy(&v, b, 8); return v; }
  }
  return 0.0;
}

/// Fewest bytes one row of `e` takes in the body.
std::uint64_t least_row_bytes(const PlyElement& e, PlyFormat format) {
  std::uint64_t bytes = 0;
  for (const auto& p : e.properties)
    bytes += format == PlyFormat::ascii ? 2 : size_of(p.list ? p.count_type : p.type);
  return bytes;
}

std::string plural(std::uint64_t n, const std::string& what) { return std::to_string(n) + " " + what; }

}  // namespace

bool host_is_little() {
  const std::uint16_t one = 1;
  unsigned char c;
  std::memcpy(&c, &one, 1);
  return c == 1;
}

std::size_t size_of(PlyType t) {
  switch (t) {
    case PlyType::int8: case PlyType::uint8: return 1;
    case PlyType::int16: case PlyType::uint16: return 2;
    case PlyType::int32: case PlyType::uint32: case PlyType::float32: return 4;
    case PlyType::float64: return 8;
  }
  return 0;
}

int PlyElement::find(std::string_view property) const {
  for (std::size_t p = 0; p < properties.size(); ++p)
    if (!properties[p].list && properties[p].name == property) return static_cast<int>(p);
  return -1;
}

const PlyElement* PlyHeader::find(std::string_view element) const {
  for (const auto& e : elements)
    if (e.name == element) return &e;
  return nullptr;
}

bool looks_like_ply(std::string_view data) {
  return data.size() >= 4 && data.substr(0, 3) == "ply" && (data[3] == '\n' || data[3] == '\r');
}

PlyHeader parse_ply_header(std::string_view data, const std::string& name) {
  if (!looks_like_ply(data)) throw InputError(name + ": not a PLY file (it does not start with 'ply')");
  PlyHeader header;
  std::size_t pos = 0;
  bool have_format = false, ended = false;
  while (pos < data.size() && !ended) {
    const std::string_view rest = data.substr(pos, std::min(data.size() - pos, kLongestHeaderLine + 1));
    std::size_t end = rest.find('\n');
    ++header.header_lines;
    const std::string where = name + ": line " + std::to_string(header.header_lines);
    if (end == std::string_view::npos) {
      if (rest.size() > kLongestHeaderLine) throw InputError(where + ": a PLY header line longer than 64 KiB");
      end = rest.size();
    }
    std::string_view line = rest.substr(0, end);
    pos += end + 1;
    if (pos > kLongestHeader) throw InputError(name + ": the PLY header is longer than 16 MiB");
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (header.header_lines == 1) continue;  // "ply"
    const auto words = words_of(line);
    if (words.empty() || words[0] == "obj_info") continue;
    if (words[0] == "comment") {
      const auto text = line.substr(std::min(line.size(), line.find("comment") + 8));
      header.comments.emplace_back(text);
    } else if (words[0] == "end_header") {
      ended = true;
    } else if (words[0] == "format") {
      if (words.size() < 2) throw InputError(where + ": PLY format line without a format");
      if (words[1] == "ascii") header.format = PlyFormat::ascii;
      else if (words[1] == "binary_little_endian") header.format = PlyFormat::little;
      else if (words[1] == "binary_big_endian") header.format = PlyFormat::big;
      else throw InputError(where + ": unknown PLY format '" + std::string(words[1]) + "'");
      have_format = true;
    } else if (words[0] == "element") {
      std::uint64_t count = 0;
      const auto w = words.size() == 3 ? words[2] : std::string_view();
      const auto parsed = std::from_chars(w.data(), w.data() + w.size(), count);
      if (words.size() != 3 || w.empty() || parsed.ec != std::errc() || parsed.ptr != w.data() + w.size())
        throw InputError(where + ": malformed element line '" + std::string(line) +
                         "' (expected 'element NAME COUNT' with a whole COUNT below 2^64)");
      header.elements.push_back({std::string(words[1]), count, {}});
    } else if (words[0] == "property") {
      if (header.elements.empty()) throw InputError(where + ": property before any element");
      PlyProperty p;
      if (words.size() == 5 && words[1] == "list") {
        p.list = true;
        if (!parse_type(words[2], p.count_type) || !parse_type(words[3], p.type))
          throw InputError(where + ": unknown PLY type in '" + std::string(line) + "'");
        if (p.count_type == PlyType::float32 || p.count_type == PlyType::float64)
          throw InputError(where + ": a list length must be an integer type in '" + std::string(line) + "'");
        p.name = words[4];
      } else if (words.size() == 3) {
        if (!parse_type(words[1], p.type))
          throw InputError(where + ": unknown PLY type '" + std::string(words[1]) + "'");
        p.name = words[2];
      } else {
        throw InputError(where + ": malformed property line '" + std::string(line) + "'");
      }
      header.elements.back().properties.push_back(p);
    } else {
      throw InputError(where + ": unexpected PLY header line '" + std::string(line) + "'");
    }
  }
  if (!ended) throw InputError(name + ": the PLY header has no end_header line");
  if (!have_format) throw InputError(name + ": the PLY header has no format line");
  header.body = std::min(pos, data.size());

  // What the counts announce must fit in what follows (an ascii file's last line end may be missing).
  std::uint64_t room = data.size() - header.body + (header.format == PlyFormat::ascii ? 1 : 0);
  for (const auto& e : header.elements) {
    const std::uint64_t row = least_row_bytes(e, header.format);
    if (row == 0) continue;
    if (e.count > room / row)
      throw InputError(name + ": the header declares " + plural(e.count, e.name) + " elements of at least " +
                       plural(row, "bytes") + " each, but only " + plural(data.size() - header.body, "bytes") +
                       " follow the header (truncated file, or a wrong count?)");
    room -= e.count * row;
  }
  return header;
}

void read_ply_body(std::string_view data, const PlyHeader& header, const std::vector<bool>& wanted,
                   const PlyRow& row, const std::string& name) {
  std::vector<double> values;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (header.format == PlyFormat::ascii) {
    std::size_t i = header.body;
    std::size_t line = header.header_lines;
    auto next_token = [&](std::string_view& token) -> bool {
      while (i < data.size() && is_space(data[i])) {
        if (data[i] == '\n') ++line;
        ++i;
      }
      if (i >= data.size()) return false;
      const std::size_t s = i;
      while (i < data.size() && !is_space(data[i])) ++i;
      token = data.substr(s, i - s);
      return true;
    };
    for (std::size_t ei = 0; ei < header.elements.size(); ++ei) {
      const PlyElement& e = header.elements[ei];
      if (e.properties.empty()) continue;
      auto number = [&](std::uint64_t k) -> double {
        std::string_view token;
        if (!next_token(token))
          throw InputError(name + ": line " + std::to_string(line + 1) + ": the data ends after " + std::to_string(k) +
                           " of the " + plural(e.count, e.name) + " elements the header declares");
        double v = 0;
        if (!parse_number(token, v))
          throw InputError(name + ": line " + std::to_string(line + 1) + ": '" + std::string(token.substr(0, 40)) +
                           "' is not a number");
        return v;
      };
      for (std::uint64_t k = 0; k < e.count; ++k) {
        values.assign(e.properties.size(), nan);
        for (std::size_t p = 0; p < e.properties.size(); ++p) {
          if (!e.properties[p].list) {
            values[p] = number(k);
            continue;
          }
          const double n = number(k);
          if (!(n >= 0) || n != std::floor(n) || n > static_cast<double>(data.size() - i))
            throw InputError(name + ": line " + std::to_string(line + 1) + ": bad list length");
          for (std::uint64_t j = 0; j < static_cast<std::uint64_t>(n); ++j) number(k);
        }
        if (wanted[ei]) row(ei, k, values.data());
      }
    }
    std::string_view extra;
    if (next_token(extra))
      throw InputError(name + ": line " + std::to_string(line + 1) + ": more data than the header declares (starting with '" +
                       std::string(extra.substr(0, 40)) + "')");
    return;
  }

  const bool swap = (header.format == PlyFormat::little) != host_is_little();
  std::size_t at = header.body;
  for (std::size_t ei = 0; ei < header.elements.size(); ++ei) {
    const PlyElement& e = header.elements[ei];
    if (e.properties.empty()) continue;
    const bool fixed = std::none_of(e.properties.begin(), e.properties.end(), [](const PlyProperty& p) { return p.list; });
    if (fixed && !wanted[ei]) {
      // The header check bounds each count, but list rows before this element may have taken more
      // than their least size: check what is left.
      const std::uint64_t bytes = e.count * least_row_bytes(e, header.format);
      if (data.size() - at < bytes)
        throw InputError(name + ": truncated: the " + plural(e.count, e.name) + " elements need " +
                         plural(bytes, "bytes") + " from byte " + std::to_string(at) + " but only " +
                         std::to_string(data.size() - at) + " follow");
      at += static_cast<std::size_t>(bytes);
      continue;
    }
    if (fixed && data.size() - at >= e.count * least_row_bytes(e, header.format)) {
      // Rows of one size that all fit: each property at its place in the row, with no check per value.
      std::vector<std::size_t> offset;
      std::size_t row_bytes = 0;
      for (const auto& prop : e.properties) {
        offset.push_back(row_bytes);
        row_bytes += size_of(prop.type);
      }
      values.assign(e.properties.size(), nan);
      for (std::uint64_t k = 0; k < e.count; ++k, at += row_bytes) {
        for (std::size_t p = 0; p < e.properties.size(); ++p)
          values[p] = read_binary(data.data() + at + offset[p], e.properties[p].type, swap);
        if (wanted[ei]) row(ei, k, values.data());
      }
      continue;
    }
    for (std::uint64_t k = 0; k < e.count; ++k) {
      values.assign(e.properties.size(), nan);
      for (std::size_t p = 0; p < e.properties.size(); ++p) {
        const auto& prop = e.properties[p];
        auto need = [&](std::uint64_t bytes) {
          if (data.size() - at < bytes)
            throw InputError(name + ": truncated at byte " + std::to_string(data.size()) + ", inside " + e.name +
                             " element " + std::to_string(k) + " of " + std::to_string(e.count));
        };
        if (prop.list) {
          need(size_of(prop.count_type));
          const double n = read_binary(data.data() + at, prop.count_type, swap);
          at += size_of(prop.count_type);
          if (n < 0) throw InputError(name + ": byte " + std::to_string(at) + ": negative list length");
          const std::uint64_t bytes = static_cast<std::uint64_t>(n) * size_of(prop.type);  // n < 2^32
          need(bytes);
          at += static_cast<std::size_t>(bytes);
        } else {
          need(size_of(prop.type));
          values[p] = read_binary(data.data() + at, prop.type, swap);
          at += size_of(prop.type);
        }
      }
      if (wanted[ei]) row(ei, k, values.data());
    }
  }
  if (at != data.size())
    throw InputError(name + ": byte " + std::to_string(at) + ": " + std::to_string(data.size() - at) +
                     " bytes follow the last element the header declares (does the header count the points right?)");
}

}  // namespace treeskel::io::detail
