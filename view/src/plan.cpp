#include "treeskel/view/plan.h"

#include "treeskel/error.h"
#include "treeskel/io/atomic_file.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <ostream>

namespace treeskel::view {

namespace {

void put_u32(std::string& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out += static_cast<char>((v >> shift) & 0xff);
}

void put_chunk(std::string& out, const char* type, const std::string& data) {
  put_u32(out, static_cast<std::uint32_t>(data.size()));
  const std::string body = std::string(type, 4) + data;
  out += body;
  put_u32(out, static_cast<std::uint32_t>(
                   ::crc32(0L, reinterpret_cast<const Bytef*>(body.data()), static_cast<uInt>(body.size()))));
}

/// 3 x 5 dots per glyph, rows from the top, bit 2 the left column.
const std::array<std::uint8_t, 5>* glyph(char c) {
  static const std::array<std::array<std::uint8_t, 5>, 13> font{{
      {7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7}, {5, 5, 7, 1, 1},
      {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 2, 2, 2}, {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7},
      {0, 0, 0, 0, 2},   // '.'
      {0, 0, 0, 0, 0},   // ' '
      {0, 0, 6, 7, 5},   // 'm'
  }};
  if (c >= '0' && c <= '9') return &font[c - '0'];
  if (c == '.') return &font[10];
  if (c == ' ') return &font[11];
  if (c == 'm') return &font[12];
  return nullptr;
}

}  // namespace

void Image::set(int x, int y, const std::array<std::uint8_t, 3>& c) {
  if (x < 0 || y < 0 || x >= width || y >= height) return;
  std::copy(c.begin(), c.end(), rgb.begin() + (static_cast<std::size_t>(y) * width + x) * 3);
}

std::string encode_png(const Image& image) {
  TREESKEL_REQUIRE(image.width > 0 && image.height > 0 && image.rgb.size() == static_cast<std::size_t>(image.width) * image.height * 3,
                   "an image with pixels");
  std::string raw;
  raw.reserve(image.rgb.size() + image.height);
  const std::size_t row = static_cast<std::size_t>(image.width) * 3;
  for (int y = 0; y < image.height; ++y) {
    raw += '\0';  // filter: none
    raw.append(reinterpret_cast<const char*>(image.rgb.data()) + y * row, row);
  }
  uLongf size = ::compressBound(static_cast<uLong>(raw.size()));
  std::string packed(size, '\0');
  if (::compress2(reinterpret_cast<Bytef*>(packed.data()), &size, reinterpret_cast<const Bytef*>(raw.data()),
                  static_cast<uLong>(raw.size()), 6) != Z_OK)
    throw Error("cannot compress the image");
  packed.resize(size);
  std::string png("\x89PNG\r\n\x1a\n", 8);
  std::string header;
  put_u32(header, static_cast<std::uint32_t>(image.width));
  put_u32(header, static_cast<std::uint32_t>(image.height));
  header += std::string("\x08\x02\x00\x00\x00", 5);  // 8 bits, RGB, deflate, no filter method, no interlace
  put_chunk(png, "IHDR", header);
  put_chunk(png, "IDAT", packed);
  put_chunk(png, "IEND", "");
  return png;
}

void write_png(const std::filesystem::path& path, const Image& image) {
  const std::string png = encode_png(image);
  io::write_atomically(path, [&](std::ostream& out) { out.write(png.data(), static_cast<std::streamsize>(png.size())); });
}

void draw_text(Image& image, int x, int y, const std::string& text, int scale, const std::array<std::uint8_t, 3>& colour) {
  for (int pass = 0; pass < 2; ++pass) {  // the outline, then the glyphs
    int left = x;
    for (char c : text) {
      const auto* g = glyph(c);
      if (g)
        for (int r = 0; r < 5; ++r)
          for (int col = 0; col < 3; ++col) {
            if (!(((*g)[r] >> (2 - col)) & 1)) continue;
            for (int dy = 0; dy < scale; ++dy)
              for (int dx = 0; dx < scale; ++dx) {
                const int px = left + col * scale + dx, py = y + r * scale + dy;
                if (pass == 1) {
                  image.set(px, py, colour);
                  continue;
                }
                for (int oy = -scale; oy <= scale; oy += scale)
                  for (int ox = -scale; ox <= scale; ox += scale) image.set(px + ox, py + oy, {255, 255, 255});
              }
          }
      left += 4 * scale;
    }
  }
}

std::array<std::uint8_t, 3> group_colour(std::uint32_t id) {
  const double hue = std::fmod(static_cast<double>(id) * 137.508, 360.0) / 60.0;
  const double s = 0.75, v = id % 2 ? 0.85 : 0.65;
  const double c = v * s, xx = c * (1 - std::abs(std::fmod(hue, 2.0) - 1)), m = v - c;
  std::array<double, 3> rgb{};
  switch (static_cast<int>(hue)) {
    case 0: rgb = {c, xx, 0}; break;
    case 1: rgb = {xx, c, 0}; break;
    case 2: rgb = {0, c, xx}; break;
    case 3: rgb = {0, xx, c}; break;
    case 4: rgb = {xx, 0, c}; break;
    default: rgb = {c, 0, xx}; break;
  }
  return {static_cast<std::uint8_t>(std::lround((rgb[0] + m) * 255)), static_cast<std::uint8_t>(std::lround((rgb[1] + m) * 255)),
          static_cast<std::uint8_t>(std::lround((rgb[2] + m) * 255))};
}

Image plan_view(const PointCloud& cloud, const std::vector<std::uint32_t>& group, const std::vector<std::uint8_t>& ground,
                const std::vector<PlanLabel>& labels, int size) {
  TREESKEL_REQUIRE(group.size() == cloud.size() && ground.size() == cloud.size(), "a group and a ground flag per point");
  TREESKEL_REQUIRE(size >= 64, "an image of at least 64 pixels");
  const Eigen::AlignedBox3d box = bounding_box(cloud);
  const double span = std::max({box.sizes().x(), box.sizes().y(), 1e-9});
  const int margin = 30;
  const double scale = (size - 2 * margin) / span;
  Image image(static_cast<int>(std::ceil(box.sizes().x() * scale)) + 2 * margin,
              static_cast<int>(std::ceil(box.sizes().y() * scale)) + 2 * margin + 30);
  auto pixel = [&](const Eigen::Vector2d& p) {
    return Eigen::Vector2i(margin + static_cast<int>((p.x() - box.min().x()) * scale),
                           image.height - 30 - margin - static_cast<int>((p.y() - box.min().y()) * scale));
  };
  // Lower points first, so a crown covers the ground and the stems under it.
  std::vector<std::uint32_t> order(cloud.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(),
            [&](std::uint32_t a, std::uint32_t b) { return cloud.positions[a].z() < cloud.positions[b].z(); });
  for (std::uint32_t p : order) {
    const std::array<std::uint8_t, 3> c = group[p] ? group_colour(group[p]) : ground[p] ? std::array<std::uint8_t, 3>{205, 200, 190}
                                                                                       : std::array<std::uint8_t, 3>{120, 120, 120};
    const Eigen::Vector2i q = pixel(cloud.positions[p].head<2>());
    image.set(q.x(), q.y(), c);
  }
  for (const auto& l : labels) {
    const Eigen::Vector2i q = pixel(l.at);
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) image.set(q.x() + dx, q.y() + dy, {0, 0, 0});
    draw_text(image, q.x() + 5, q.y() - 7, l.text, 3, {0, 0, 0});
  }
  // A scale bar of a round length near a fifth of the plot, at the bottom left.
  const double target = span / 5;
  double bar = std::pow(10.0, std::floor(std::log10(target)));
  for (double step : {2.0, 5.0})
    if (bar * step <= target) bar = std::pow(10.0, std::floor(std::log10(target))) * step;
  const int length = static_cast<int>(bar * scale), y = image.height - 20;
  for (int x = margin; x <= margin + length; ++x)
    for (int t = 0; t < 3; ++t) image.set(x, y + t, {0, 0, 0});
  std::string text = std::to_string(bar);
  text.erase(text.find_last_not_of('0') + 1);
  if (text.back() == '.') text.pop_back();
  draw_text(image, margin + length + 8, y - 6, text + " m", 3, {0, 0, 0});
  return image;
}

}  // namespace treeskel::view
