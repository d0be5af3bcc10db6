/// @file html.h
/// A self-contained HTML page of one tree (its cloud, skeleton and mesh, and its report) that opens
/// from disk in a current browser with no network: three.js is inlined (bundled at build time from
/// npm, with its licence), the geometry is in the page, deflated and base64-encoded. And a PNG preview
/// of the same scene from the side and from above, rendered by headless Chromium.
#pragma once

#include "treeskel/modeling/tree_mesh.h"
#include "treeskel/point_cloud.h"
#include "treeskel/skeleton.h"

#include <nlohmann/json.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace treeskel::view {

/// What the tool did with a point, as the page colours it.
enum class PointClass : std::uint8_t { tree = 0, left_out = 1, leaf = 2 };

/// A piece of skeleton in the input's frame, with its branch order (0: the trunk) and radius.
struct Segment {
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();
  int order = 0;
  double radius = 0.0;
};

/// What one page shows. Everything is optional but the title; coordinates are the input's (local +
/// offset), and the page places them around the scene's centre in 32-bit floats.
struct Scene {
  std::string title;
  const PointCloud* cloud = nullptr;
  std::vector<PointClass> classes;  ///< empty (all in the tree), or one per point of `cloud`
  std::vector<Segment> skeleton;
  const modeling::TreeMesh* mesh = nullptr;
  Eigen::Vector3d mesh_offset = Eigen::Vector3d::Zero();  ///< a mesh point + this = the input's frame
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();          ///< the tree's up axis in the input's frame
  nlohmann::ordered_json report = nlohmann::ordered_json::object();  ///< shown beside the view
};

struct HtmlOptions {
  /// At most this many points of the cloud go into the page (every k-th point, evenly over the file;
  /// the page says how many it shows). Browsers draw a few million points, but the page's size grows
  /// by about 13 bytes a point.
  std::size_t max_points = 400000;
};

/// The skeleton's edges as segments in the input's frame, with branch orders: at each fork the
/// child with the longest path to a tip continues its parent's order, the others start one higher.
/// Radii are the nodes' (the mean of the edge's two ends). @throws InputError when it is not a tree.
std::vector<Segment> skeleton_segments(const Skeleton& skeleton);

/// The point classes of `cloud` as `skeleton` left them: a point no node stands for is left out.
std::vector<PointClass> point_classes(const PointCloud& cloud, const Skeleton& skeleton);

/// `text` with &, <, > and " written as HTML entities.
std::string escape_html(const std::string& text);

/// The page, as text.
std::string html_page(const Scene& scene, const HtmlOptions& options = {});

/// Writes the page to `path`. @throws Error when it cannot be written.
void write_html(const std::filesystem::path& path, const Scene& scene, const HtmlOptions& options = {});

/// The Chromium (or Chrome) to render previews with: $TREESKEL_CHROMIUM, else the first of chromium,
/// chromium-browser, google-chrome on the PATH; "" when there is none (or $TREESKEL_CHROMIUM is not
/// an executable).
std::string find_chromium();

/// Renders the preview of a page written by `write_html` (the side view and the view from above, side
/// by side) into `png`, `width` x `height` pixels, with headless Chromium and a software WebGL: no
/// display is needed. @throws Error when Chromium is missing or fails, or the page shows nothing.
void render_preview(const std::filesystem::path& html, const std::filesystem::path& png, int width = 1600,
                    int height = 800);

}  // namespace treeskel::view
