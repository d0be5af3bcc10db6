// The plan view and its PNG: a valid PNG whose pixels read back, colours per group, labels drawn.
#include "treeskel/view/plan.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <set>

namespace treeskel::view {
namespace {

std::uint32_t be32(const std::string& s, std::size_t at) {
  return (static_cast<std::uint32_t>(static_cast<unsigned char>(s[at])) << 24) |
         (static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 1])) << 16) |
         (static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 2])) << 8) |
         static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 3]));
}

/// The image's pixels back from its PNG: chunks walked with their CRCs checked, IDAT inflated.
Image decode(const std::string& png) {
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  Image image;
  std::string data;
  for (std::size_t at = 8; at + 12 <= png.size();) {
    const std::uint32_t length = be32(png, at);
    const std::string type = png.substr(at + 4, 4);
    const std::string body = png.substr(at + 4, 4 + length);
    EXPECT_EQ(be32(png, at + 8 + length),
              static_cast<std::uint32_t>(::crc32(0L, reinterpret_cast<const Bytef*>(body.data()), static_cast<uInt>(body.size()))))
        << type;
    if (type == "IHDR") {
      image.width = static_cast<int>(be32(png, at + 8));
      image.height = static_cast<int>(be32(png, at + 12));
    }
    if (type == "IDAT") data += png.substr(at + 8, length);
    at += 12 + length;
  }
  std::string raw(static_cast<std::size_t>(image.width) * image.height * 3 + image.height, '\0');
  uLongf size = raw.size();
  EXPECT_EQ(::uncompress(reinterpret_cast<Bytef*>(raw.data()), &size, reinterpret_cast<const Bytef*>(data.data()), data.size()), Z_OK);
  EXPECT_EQ(size, raw.size());
  for (int y = 0; y < image.height; ++y) {
    EXPECT_EQ(raw[y * (image.width * 3 + 1)], '\0');
    image.rgb.insert(image.rgb.end(), raw.begin() + y * (image.width * 3 + 1) + 1, raw.begin() + (y + 1) * (image.width * 3 + 1));
  }
  return image;
}

TEST(Png, PixelsReadBack) {
  Image image(3, 2);
  image.set(0, 0, {255, 0, 0});
  image.set(2, 1, {1, 2, 3});
  image.set(5, 5, {9, 9, 9});  // outside: ignored
  const Image back = decode(encode_png(image));
  EXPECT_EQ(back.width, 3);
  EXPECT_EQ(back.height, 2);
  EXPECT_EQ(back.rgb, image.rgb);
}

TEST(GroupColour, NeighbouringIdsDiffer) {
  std::set<std::array<std::uint8_t, 3>> seen;
  for (std::uint32_t id = 1; id <= 40; ++id) {
    seen.insert(group_colour(id));
    EXPECT_NE(group_colour(id), group_colour(id + 1));
  }
  EXPECT_GE(seen.size(), 38u);
}

TEST(PlanView, EachGroupInItsColourAndTheLabelsDrawn) {
  PointCloud cloud;
  std::vector<std::uint32_t> group;
  std::vector<std::uint8_t> ground;
  for (int i = 0; i <= 100; ++i)
    for (int j = 0; j <= 50; ++j) {
      cloud.positions.emplace_back(i * 0.1, j * 0.1, 0.0);
      group.push_back(i < 50 ? 1 : 2);
      ground.push_back(0);
    }
  cloud.positions.emplace_back(2.5, 2.5, -1.0);  // a ground point below group 1: drawn under it
  group.push_back(0);
  ground.push_back(1);
  const Image image = plan_view(cloud, group, ground, {{{2.5, 2.5}, "12"}}, 400);
  EXPECT_GT(image.width, image.height);
  std::size_t colour1 = 0, colour2 = 0, black = 0, ground_grey = 0;
  for (std::size_t p = 0; p + 2 < image.rgb.size(); p += 3) {
    const std::array<std::uint8_t, 3> c{image.rgb[p], image.rgb[p + 1], image.rgb[p + 2]};
    colour1 += c == group_colour(1);
    colour2 += c == group_colour(2);
    black += c == std::array<std::uint8_t, 3>{0, 0, 0};
    ground_grey += c == std::array<std::uint8_t, 3>{205, 200, 190};
  }
  EXPECT_GT(colour1, 1000u);
  EXPECT_GT(colour2, 1000u);
  EXPECT_GT(black, 100u);  // the label, its mark and the scale bar
  EXPECT_EQ(ground_grey, 0u);
}

}  // namespace
}  // namespace treeskel::view
