/// @file plan.h
/// A plot seen from above as a PNG: each tree's points in a colour of its own, the ground and the
/// points of no tree in greys, higher points drawn over lower ones, each tree's id at its stem and a
/// scale bar. Written by our own PNG encoder (zlib), so no browser or display is needed.
#pragma once

#include "treeskel/point_cloud.h"

#include <Eigen/Core>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace treeskel::view {

/// An RGB image, rows from the top.
struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  ///< width * height * 3

  Image() = default;
  Image(int w, int h, std::uint8_t grey = 255) : width(w), height(h), rgb(static_cast<std::size_t>(w) * h * 3, grey) {}
  void set(int x, int y, const std::array<std::uint8_t, 3>& c);
};

/// Encodes the image as PNG (8-bit RGB, zlib-compressed rows, no filter).
std::string encode_png(const Image& image);

/// Writes the PNG atomically. @throws Error when it cannot be written.
void write_png(const std::filesystem::path& path, const Image& image);

/// Draws `text` (digits, '.', ' ' and 'm') with its top-left corner at (x, y), `scale` pixels a font dot,
/// in `colour` over a one-dot white outline.
void draw_text(Image& image, int x, int y, const std::string& text, int scale, const std::array<std::uint8_t, 3>& colour);

/// The colour of group `id` (> 0): hues spread by the golden angle, so neighbouring ids differ.
std::array<std::uint8_t, 3> group_colour(std::uint32_t id);

struct PlanLabel {
  Eigen::Vector2d at = Eigen::Vector2d::Zero();  ///< local frame, like the cloud's positions
  std::string text;
};

/// The plan view: `group` per point (0: in no group), `ground` per point (1: ground), labels at
/// their places. The longer side of the plot gets `size` pixels.
Image plan_view(const PointCloud& cloud, const std::vector<std::uint32_t>& group, const std::vector<std::uint8_t>& ground,
                const std::vector<PlanLabel>& labels, int size = 1200);

}  // namespace treeskel::view
