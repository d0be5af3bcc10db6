// Uncompressed ASPRS LAS 1.0 to 1.4, point data formats 0 to 10. Positions are X·scale + offset in
// doubles; RGB is read where the format has it. LAZ (compressed) files go through laz.cpp.
#include "formats.h"

#include "treeskel/error.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <ostream>
#include <utility>

namespace treeskel::io::detail {

namespace {

template <class T>
T get(std::string_view data, std::size_t at) {
  T v;
  std::memcpy(&v, data.data() + at, sizeof(T));  // LAS is little-endian, as is every host we build on
  return v;
}

template <class T>
void put(std::string& out, T v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

constexpr std::size_t minimum_record[] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
constexpr int rgb_offset[] = {-1, -1, 20, 28, -1, 28, -1, 30, 30, -1, 30};

}  // namespace

PointCloud read_las(std::string_view data, const std::string& name) {
  if (data.size() < 4 || data.compare(0, 4, "LASF") != 0)
    throw InputError(name + ": not a LAS file (it does not start with 'LASF')");
  if (data.size() < 227)
    throw InputError(name + ": truncated: " + std::to_string(data.size()) + " bytes, shorter than a LAS header (227)");
  const int major = static_cast<unsigned char>(data[24]), minor = static_cast<unsigned char>(data[25]);
  if (major != 1 || minor > 4)
    throw InputError(name + ": LAS version " + std::to_string(major) + "." + std::to_string(minor) +
                     " is not supported (1.0 to 1.4 are)");
  const std::size_t header_size = get<std::uint16_t>(data, 94);
  const std::size_t point_offset = get<std::uint32_t>(data, 96);
  const unsigned format_byte = static_cast<unsigned char>(data[104]);
  const std::size_t record = get<std::uint16_t>(data, 105);
  if (format_byte & 0xC0)
    throw InputError(name + ": is LAZ-compressed: name it .laz to have it decompressed (with laz-perf under "
                            "Node.js), or decompress it first with 'laszip' or 'pdal translate'");
  const unsigned format = format_byte;
  if (format > 10) throw InputError(name + ": LAS point data format " + std::to_string(format) + " is unknown");
  if (record < minimum_record[format])
    throw InputError(name + ": byte 105: point record length " + std::to_string(record) + " is shorter than format " +
                     std::to_string(format) + " needs (" + std::to_string(minimum_record[format]) + ")");
  const std::size_t needed_header = minor >= 4 ? 375 : minor == 3 ? 235 : 227;
  if (header_size < needed_header || data.size() < needed_header)
    throw InputError(name + ": byte 94: header size " + std::to_string(header_size) + " is too small for LAS 1." +
                     std::to_string(minor));
  std::uint64_t count = get<std::uint32_t>(data, 107);
  std::size_t data_end = data.size();
  if (minor >= 4) {
    const auto extended = get<std::uint64_t>(data, 247);
    if (count == 0 || format >= 6) count = extended;
    const auto evlr = get<std::uint64_t>(data, 235);
    if (evlr > point_offset && evlr <= data.size()) data_end = evlr;
  }
  if (minor == 3 || minor == 4) {
    const auto waveform = get<std::uint64_t>(data, 227);
    if (waveform > point_offset && waveform < data_end) data_end = waveform;
  }
  if (point_offset > data.size())
    throw InputError(name + ": truncated: point data should start at byte " + std::to_string(point_offset) +
                     " but the file has " + std::to_string(data.size()) + " bytes");
  const std::size_t available = (data_end - point_offset) / record;
  if (count > available)
    throw InputError(name + ": truncated: the header declares " + std::to_string(count) + " points of " +
                     std::to_string(record) + " bytes from byte " + std::to_string(point_offset) + ", but only " +
                     std::to_string(data_end - point_offset) + " bytes follow");
  if (point_offset + count * record != data_end)
    throw InputError(name + ": byte " + std::to_string(point_offset + count * record) + ": the header declares " +
                     std::to_string(count) + " points but " + std::to_string(data_end - point_offset - count * record) +
                     " more bytes of point data follow");
  const double scale[3] = {get<double>(data, 131), get<double>(data, 139), get<double>(data, 147)};
  const double offset[3] = {get<double>(data, 155), get<double>(data, 163), get<double>(data, 171)};
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(scale[a]) || scale[a] == 0.0 || !std::isfinite(offset[a]))
      throw InputError(name + ": byte " + std::to_string(131 + 8 * a) + ": the scale or offset of axis " +
                       std::string(1, "xyz"[a]) + " is not usable");
  if (count == 0) throw InputError(name + ": holds no points");

  PointCloud cloud;
  cloud.positions.resize(count);
  const int rgb = rgb_offset[format];
  if (rgb >= 0) cloud.colors.resize(count);
  bool wide_colors = false;
  // The class: the low five bits of byte 15 in formats 0-5, all of byte 16 in formats 6-10.
  const std::size_t class_at = format >= 6 ? 16 : 15;
  const std::uint8_t class_mask = format >= 6 ? 0xff : 0x1f;
  cloud.classes.resize(count);
  bool classified = false;
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t at = point_offset + i * record;
    cloud.classes[i] = get<std::uint8_t>(data, at + class_at) & class_mask;
    classified |= cloud.classes[i] > 1;
    for (int a = 0; a < 3; ++a)
      cloud.positions[i][a] = get<std::int32_t>(data, at + 4 * a) * scale[a] + offset[a];
    if (rgb >= 0)
      for (int a = 0; a < 3; ++a) {
        const auto c = get<std::uint16_t>(data, at + rgb + 2 * a);
        wide_colors |= c > 255;
        cloud.colors[i][a] = static_cast<std::uint8_t>(std::min<unsigned>(c, 255));
      }
  }
  if (!classified) cloud.classes.clear();
  if (wide_colors)  // 16-bit colours, as the standard asks: scale them down
    for (std::size_t i = 0; i < count; ++i)
      for (int a = 0; a < 3; ++a)
        cloud.colors[i][a] = static_cast<std::uint8_t>(get<std::uint16_t>(data, point_offset + i * record + rgb + 2 * a) >> 8);
  return cloud;
}

namespace {

/// The LAS "extra bytes" data type of a field (LAS 1.4 R15, table 24) and its size.
std::pair<std::uint8_t, std::size_t> extra_type(PointField::Type t) {
  switch (t) {
    case PointField::Type::uint8: return {1, 1};
    case PointField::Type::uint32: return {5, 4};
    case PointField::Type::float32: return {9, 4};
  }
  return {9, 4};
}

/// The extra bytes VLR (user "LASF_Spec", record 4): a 54-byte header and a 192-byte descriptor per
/// field, each naming the field and its type.
std::string extra_bytes_vlr(const std::vector<PointField>& fields) {
  std::string v(54 + 192 * fields.size(), '\0');
  std::memcpy(&v[2], "LASF_Spec", 9);
  const std::uint16_t id = 4, length = static_cast<std::uint16_t>(192 * fields.size());
  std::memcpy(&v[18], &id, 2);
  std::memcpy(&v[20], &length, 2);
  std::memcpy(&v[22], "Extra bytes", 11);
  for (std::size_t i = 0; i < fields.size(); ++i) {
    char* d = &v[54 + 192 * i];
    d[2] = static_cast<char>(extra_type(fields[i].type).first);
    std::memcpy(d + 4, fields[i].name.data(), std::min<std::size_t>(fields[i].name.size(), 32));
    const std::string about = "treeskel " + fields[i].name;
    std::memcpy(d + 160, about.data(), std::min<std::size_t>(about.size(), 32));
  }
  return v;
}

}  // namespace

void write_las(std::ostream& out, const PointCloud& cloud, const std::vector<PointField>& fields) {
  for (const auto& f : fields)
    if (f.name.empty() || f.name.size() > 32) throw Error("a LAS extra bytes field needs a name of 1 to 32 characters, not '" + f.name + "'");
  const bool colors = cloud.has_colors();
  const std::uint8_t format = colors ? 2 : 0;
  std::size_t extra = 0;
  for (const auto& f : fields) extra += extra_type(f.type).second;
  const auto record = static_cast<std::uint16_t>((colors ? 26 : 20) + extra);
  Eigen::AlignedBox3d box;
  for (const auto& p : cloud.positions) box.extend(p + cloud.offset);
  if (cloud.empty()) box.extend(Eigen::Vector3d::Zero());
  Eigen::Vector3d offset, scale;
  for (int a = 0; a < 3; ++a) {
    offset[a] = std::floor(box.min()[a]);
    const double extent = box.max()[a] - offset[a];
    scale[a] = 1e-4;
    while (extent / scale[a] > 2.0e9) scale[a] *= 10.0;
  }
  // LAS 1.2, or 1.4 (whose header is 375 bytes) when the points carry extra bytes, which that
  // version describes.
  const bool v14 = !fields.empty();
  const std::string vlr = v14 ? extra_bytes_vlr(fields) : std::string();
  const std::uint16_t header_size = v14 ? 375 : 227;
  std::string h(header_size, '\0');
  h.replace(0, 4, "LASF");
  h[24] = 1;
  h[25] = v14 ? 4 : 2;
  const char software[] = "treeskel";
  std::memcpy(&h[58], software, sizeof software - 1);
  auto set = [&](std::size_t at, auto v) { std::memcpy(&h[at], &v, sizeof v); };
  set(94, header_size);
  set(96, static_cast<std::uint32_t>(header_size + vlr.size()));
  set(100, static_cast<std::uint32_t>(v14 ? 1 : 0));
  set(104, format);
  set(105, record);
  const bool legacy_count = cloud.size() <= 0xffffffffu;
  set(107, static_cast<std::uint32_t>(legacy_count ? cloud.size() : 0));
  set(111, static_cast<std::uint32_t>(legacy_count ? cloud.size() : 0));
  for (int a = 0; a < 3; ++a) {
    set(131 + 8 * a, scale[a]);
    set(155 + 8 * a, offset[a]);
    set(179 + 16 * a, box.max()[a]);
    set(187 + 16 * a, box.min()[a]);
  }
  if (v14) {
    set(247, static_cast<std::uint64_t>(cloud.size()));  // points
    set(255, static_cast<std::uint64_t>(cloud.size()));  // of which first returns
  }
  out.write(h.data(), static_cast<std::streamsize>(h.size()));
  out.write(vlr.data(), static_cast<std::streamsize>(vlr.size()));
  std::string buffer;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d p = cloud.positions[i] + cloud.offset;
    for (int a = 0; a < 3; ++a) put(buffer, static_cast<std::int32_t>(std::llround((p[a] - offset[a]) / scale[a])));
    put(buffer, std::uint16_t{0});  // intensity
    put(buffer, std::uint8_t{0x09});  // return 1 of 1
    put(buffer, static_cast<std::uint8_t>(cloud.classes.empty() ? 0 : cloud.classes[i] & 0x1f));  // classification
    put(buffer, std::int8_t{0});      // scan angle
    put(buffer, std::uint8_t{0});     // user data
    put(buffer, std::uint16_t{0});    // point source
    if (colors)
      for (int a = 0; a < 3; ++a) put(buffer, static_cast<std::uint16_t>(cloud.colors[i][a] * 257));
    for (const auto& f : fields) {
      const double x = f.values[i];
      switch (f.type) {
        case PointField::Type::uint8: put(buffer, static_cast<std::uint8_t>(x)); break;
        case PointField::Type::uint32: put(buffer, static_cast<std::uint32_t>(x)); break;
        case PointField::Type::float32: put(buffer, static_cast<float>(x)); break;
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
