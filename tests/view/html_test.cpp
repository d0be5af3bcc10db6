#include "support/synthetic.h"
#include "treeskel/error.h"
#include "treeskel/view/html.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <zlib.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace treeskel::view {
namespace {

using nlohmann::json;

/// The text between `open` (after it) and the next `close`.
std::string between(const std::string& text, const std::string& open, const std::string& close) {
  const auto a = text.find(open);
  if (a == std::string::npos) return "";
  const auto b = text.find(close, a + open.size());
  return text.substr(a + open.size(), b - a - open.size());
}

std::vector<unsigned char> from_base64(const std::string& text) {
  std::vector<unsigned char> out;
  unsigned v = 0;
  int bits = 0;
  for (char c : text) {
    int d = -1;
    if (c >= 'A' && c <= 'Z') d = c - 'A';
    else if (c >= 'a' && c <= 'z') d = c - 'a' + 26;
    else if (c >= '0' && c <= '9') d = c - '0' + 52;
    else if (c == '+') d = 62;
    else if (c == '/') d = 63;
    if (d < 0) continue;
    v = (v << 6) | static_cast<unsigned>(d);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>((v >> bits) & 255));
    }
  }
  return out;
}

/// A page's scene manifest and its data, decoded as the page's script decodes them.
struct Decoded {
  json manifest;
  std::vector<unsigned char> bytes;
  template <typename T>
  std::vector<T> array(const std::string& name) const {
    if (!manifest["arrays"].contains(name)) return {};
    const auto& e = manifest["arrays"][name];
    std::vector<T> out(e["count"].get<std::size_t>());
    std::memcpy(out.data(), bytes.data() + e["offset"].get<std::size_t>(), out.size() * sizeof(T));
    return out;
  }
  /// Positions, quantized by the page to 16-bit steps across the scene's box, as the page reads them.
  std::vector<double> positions(const std::string& name) const {
    const auto q = array<std::uint16_t>(name);
    std::vector<double> out;
    if (q.empty()) return out;
    const auto& e = manifest["arrays"][name];
    EXPECT_EQ(e["type"], "uint16");
    for (std::size_t i = 0; i < q.size(); ++i) out.push_back(e["min"][i % 3].get<double>() + q[i] * e["step"][i % 3].get<double>());
    return out;
  }
};

Decoded decode(const std::string& page) {
  Decoded d;
  d.manifest = json::parse(between(page, "<script type=\"application/json\" id=\"treeskel-scene\">", "</script>"));
  const auto packed = from_base64(between(page, "<script type=\"application/octet-stream\" id=\"treeskel-data\">", "</script>"));
  uLongf size = 64 << 20;
  d.bytes.resize(size);
  EXPECT_EQ(::uncompress(d.bytes.data(), &size, packed.data(), static_cast<uLong>(packed.size())), Z_OK);
  d.bytes.resize(size);
  return d;
}

PointCloud five_points() {
  PointCloud c;
  for (int i = 0; i < 5; ++i) c.positions.emplace_back(i, 2.0 * i, 0.5);
  c.offset = Eigen::Vector3d(1000.0, 2000.0, 10.0);
  return c;
}

/// root 0 - 1 - 2 (a fork), 2 - 3 - 4 (long), 2 - 5 (short).
Skeleton small_fork() {
  Skeleton s;
  const std::vector<Eigen::Vector3d> at{{0, 0, 0}, {0, 0, 1}, {0, 0, 2}, {0, 0, 3}, {0, 0, 4}, {0.5, 0, 2.5}};
  for (const auto& p : at) {
    SkeletonNode n;
    n.position = p;
    n.radius = 0.1;
    add_node(s, n);
  }
  for (auto [a, b] : std::vector<std::pair<int, int>>{{0, 1}, {1, 2}, {2, 3}, {3, 4}, {2, 5}})
    boost::add_edge(static_cast<NodeId>(a), static_cast<NodeId>(b), s.graph);
  s.root = 0;
  return s;
}

TEST(Html, PageCarriesTheViewerAndDecodesToTheScene) {
  const PointCloud cloud = five_points();
  Scene scene;
  scene.title = "tree.xyz";
  scene.cloud = &cloud;
  scene.classes = {PointClass::tree, PointClass::left_out, PointClass::tree, PointClass::leaf, PointClass::tree};
  scene.skeleton = {{Eigen::Vector3d(1000, 2000, 10), Eigen::Vector3d(1000, 2000, 11), 0, 0.2}};
  modeling::TreeMesh mesh;
  const auto a = mesh.add_vertex({0, 0, 0}), b = mesh.add_vertex({1, 0, 0}), c = mesh.add_vertex({0, 1, 0}),
             d = mesh.add_vertex({0, 0, 1});
  mesh.add_face(a, c, b);
  mesh.add_face(a, b, d);
  mesh.add_face(a, d, c);
  mesh.add_face(b, c, d);
  scene.mesh = &mesh;
  scene.mesh_offset = cloud.offset;
  scene.report = {{"points", 5}, {"warnings", {"a </script> in a warning"}}};
  const std::string page = html_page(scene);

  // No network: the script is inline, nothing is fetched.
  EXPECT_EQ(page.find("src="), std::string::npos);
  EXPECT_EQ(page.find("href="), std::string::npos);
  EXPECT_NE(page.find("three.js"), std::string::npos);
  EXPECT_NE(page.find("MIT"), std::string::npos);  // three.js's licence travels with it
  // The report's text cannot end its script element early.
  EXPECT_EQ(page.find("a </script>"), std::string::npos);

  const Decoded decoded = decode(page);
  EXPECT_EQ(decoded.manifest["title"], "tree.xyz");
  EXPECT_EQ(decoded.manifest["report"]["warnings"][0], "a </script> in a warning");
  EXPECT_EQ(decoded.manifest["shown_points"], 5);
  const Eigen::Vector3d centre(decoded.manifest["centre"][0], decoded.manifest["centre"][1], decoded.manifest["centre"][2]);
  // The box of everything: points x 0..4, y 0..8, z 0.5; the segment's z 0..1; the mesh 0..1.
  EXPECT_DOUBLE_EQ(centre.x(), 1002.0);
  EXPECT_DOUBLE_EQ(centre.y(), 2004.0);
  EXPECT_DOUBLE_EQ(centre.z(), 10.5);
  // To within half a step of 1/65535 of the box (4 x 8 x 1).
  const auto points = decoded.positions("points");
  ASSERT_EQ(points.size(), 15u);
  for (int i = 0; i < 5; ++i) {
    EXPECT_NEAR(points[3 * i], i - 2.0, 4.0 / 65535);
    EXPECT_NEAR(points[3 * i + 1], 2.0 * i - 4.0, 8.0 / 65535);
    EXPECT_NEAR(points[3 * i + 2], 0.0, 1.0 / 65535);
  }
  EXPECT_EQ(decoded.array<std::uint8_t>("classes"), (std::vector<std::uint8_t>{0, 1, 0, 2, 0}));
  const std::vector<double> ends{-2, -4, -0.5, -2, -4, 0.5};
  const auto segments = decoded.positions("segments");
  ASSERT_EQ(segments.size(), ends.size());
  for (std::size_t i = 0; i < ends.size(); ++i) EXPECT_NEAR(segments[i], ends[i], 1e-4);
  EXPECT_EQ(decoded.array<float>("segment_radii"), (std::vector<float>{0.2f}));
  EXPECT_EQ(decoded.array<std::uint8_t>("segment_orders"), (std::vector<std::uint8_t>{0}));
  EXPECT_EQ(decoded.positions("vertices").size(), 12u);
  EXPECT_EQ(decoded.array<std::uint32_t>("triangles").size(), 12u);
  EXPECT_EQ(decoded.array<std::uint32_t>("triangles")[1], 2u);
}

TEST(Html, LargeCloudsAreThinnedEvenly) {
  const PointCloud cloud = five_points();
  Scene scene;
  scene.title = "t";
  scene.cloud = &cloud;
  HtmlOptions options;
  options.max_points = 2;
  const Decoded decoded = decode(html_page(scene, options));
  EXPECT_EQ(decoded.manifest["shown_points"], 2);
  const auto points = decoded.positions("points");
  ASSERT_EQ(points.size(), 6u);
  EXPECT_NEAR(points[0], -2.0, 1e-4);  // point 0 (x 0, around the whole cloud's centre 2)
  EXPECT_NEAR(points[3], 0.0, 1e-4);   // point 2
}

TEST(Html, TitleIsEscaped) {
  Scene scene;
  scene.title = "<b>&\"";
  const std::string page = html_page(scene);
  EXPECT_NE(page.find("<title>&lt;b&gt;&amp;&quot; - treeskel</title>"), std::string::npos);
  EXPECT_EQ(escape_html("a<b>&\"c"), "a&lt;b&gt;&amp;&quot;c");
}

TEST(Html, SegmentsFollowTheLongestPathAtForks) {
  Skeleton s = small_fork();
  s.offset = Eigen::Vector3d(10, 20, 30);
  const auto segments = skeleton_segments(s);
  ASSERT_EQ(segments.size(), 5u);
  for (const auto& seg : segments) {
    const bool to_twig = seg.b.x() > 10.0;  // the short branch to node 5
    EXPECT_EQ(seg.order, to_twig ? 1 : 0);
    EXPECT_DOUBLE_EQ(seg.radius, 0.1);
    EXPECT_GE(seg.a.z(), 30.0);  // in the input's frame
  }
  boost::add_edge(4, 5, s.graph);  // a cycle: not a skeleton
  EXPECT_THROW(skeleton_segments(s), InputError);
}

TEST(Html, PointsNoNodeStandsForAreLeftOut) {
  Skeleton s = small_fork();
  s[0].points = {0, 2};
  s[3].points = {4};
  const PointCloud cloud = five_points();
  EXPECT_EQ(point_classes(cloud, s), (std::vector<PointClass>{PointClass::tree, PointClass::left_out, PointClass::tree,
                                                              PointClass::left_out, PointClass::tree}));
}

TEST(Html, WriteHtmlWritesThePage) {
  test::TempDir dir;
  Scene scene;
  scene.title = "t";
  const auto path = std::filesystem::path(dir.path("p.html"));
  write_html(path, scene);
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), html_page(scene));
  EXPECT_THROW(write_html(std::filesystem::path(dir.path("missing/p.html")), scene), Error);
}

TEST(Html, PreviewWithoutChromiumSaysWhatToInstall) {
  ::setenv("TREESKEL_CHROMIUM", "/nonexistent/chromium", 1);
  EXPECT_EQ(find_chromium(), "");
  test::TempDir dir;
  try {
    render_preview(std::filesystem::path(dir.path("p.html")), dir.path("p.png"));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("apt-get install chromium"), std::string::npos) << e.what();
  }
  ::unsetenv("TREESKEL_CHROMIUM");
}

}  // namespace
}  // namespace treeskel::view
