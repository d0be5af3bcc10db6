#include "treeskel/view/html.h"

#include "treeskel/error.h"
#include "treeskel/io/atomic_file.h"
#include "treeskel/io/run_program.h"
#include "treeskel/modeling/chains.h"

#include <zlib.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>
#include <unistd.h>

namespace treeskel::view {

namespace detail {
extern const std::string_view kViewerScript;
extern const std::string_view kThreeVersion;
}  // namespace detail

namespace {

namespace fs = std::filesystem;

/// The page's binary payload: arrays one after the other, each aligned to 4 bytes.
class Payload {
 public:
  template <typename T>
  void add(const std::string& name, const std::vector<T>& values) {
    while (bytes_.size() % 4 != 0) bytes_.push_back(0);
    manifest_[name] = {{"offset", bytes_.size()}, {"count", values.size()}};
    const auto* p = reinterpret_cast<const unsigned char*>(values.data());
    bytes_.insert(bytes_.end(), p, p + values.size() * sizeof(T));
  }
  /// Points (x, y, z after one another) as 16-bit integers across `box`: a 30 m plot to half a
  /// millimetre, at half the bytes of floats and deflating far better.
  void add_quantized(const std::string& name, const std::vector<float>& xyz, const Eigen::AlignedBox3d& box) {
    std::vector<std::uint16_t> q(xyz.size());
    const Eigen::Vector3d size = box.sizes().cwiseMax(1e-12);
    for (std::size_t i = 0; i < xyz.size(); ++i) {
      const int k = static_cast<int>(i % 3);
      const double t = (static_cast<double>(xyz[i]) - box.min()[k]) / size[k];
      q[i] = static_cast<std::uint16_t>(std::lround(std::clamp(t, 0.0, 1.0) * 65535.0));
    }
    add(name, q);
    manifest_[name]["type"] = "uint16";
    manifest_[name]["min"] = {box.min().x(), box.min().y(), box.min().z()};
    manifest_[name]["step"] = {size.x() / 65535.0, size.y() / 65535.0, size.z() / 65535.0};
  }
  const std::vector<unsigned char>& bytes() const { return bytes_; }
  const nlohmann::ordered_json& manifest() const { return manifest_; }

 private:
  std::vector<unsigned char> bytes_;
  nlohmann::ordered_json manifest_ = nlohmann::ordered_json::object();
};

std::vector<unsigned char> deflate(const std::vector<unsigned char>& in) {
  uLongf size = ::compressBound(static_cast<uLong>(in.size()));
  std::vector<unsigned char> out(size);
  if (::compress2(out.data(), &size, in.data(), static_cast<uLong>(in.size()), 6) != Z_OK)
    throw Error("could not compress the page's data");
  out.resize(size);
  return out;
}

std::string base64(const std::vector<unsigned char>& in) {
  static const char* const digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4 + in.size() / 57);
  std::size_t line = 0;
  for (std::size_t i = 0; i < in.size(); i += 3) {
    const unsigned v = (unsigned{in[i]} << 16) | (i + 1 < in.size() ? unsigned{in[i + 1]} << 8 : 0u) |
                       (i + 2 < in.size() ? unsigned{in[i + 2]} : 0u);
    out += digits[(v >> 18) & 63];
    out += digits[(v >> 12) & 63];
    out += i + 1 < in.size() ? digits[(v >> 6) & 63] : '=';
    out += i + 2 < in.size() ? digits[v & 63] : '=';
    if (++line == 256) {  // lines of 1024 characters: editors and diff tools cope
      out += '\n';
      line = 0;
    }
  }
  return out;
}

/// JSON that can sit inside a <script> element: "</" cannot end it early.
std::string script_json(const nlohmann::ordered_json& j) {
  std::string text = j.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '<' && i + 1 < text.size() && text[i + 1] == '/') {
      out += "<\\/";
      ++i;
    } else {
      out += text[i];
    }
  }
  return out;
}

/// Where the page's floats are measured from: the middle of what it shows, so that 32-bit floats
/// keep georeferenced coordinates to well under a millimetre.
Eigen::Vector3d scene_centre(const Scene& scene) {
  Eigen::AlignedBox3d box;
  if (scene.cloud)
    for (const auto& p : scene.cloud->positions) box.extend(p + scene.cloud->offset);
  for (const auto& s : scene.skeleton) {
    box.extend(s.a);
    box.extend(s.b);
  }
  if (scene.mesh)
    for (auto v : scene.mesh->vertices()) {
      const auto p = scene.mesh->point(v);
      box.extend(Eigen::Vector3d(p[0], p[1], p[2]) + scene.mesh_offset);
    }
  if (box.isEmpty()) return Eigen::Vector3d::Zero();
  return box.center();
}

void push(std::vector<float>& out, const Eigen::Vector3d& p) {
  out.push_back(static_cast<float>(p.x()));
  out.push_back(static_cast<float>(p.y()));
  out.push_back(static_cast<float>(p.z()));
}

const char* const kStyle = R"css(
html, body { margin: 0; height: 100%; font: 14px/1.4 system-ui, -apple-system, "Segoe UI", sans-serif; color: #222; background: #f7f7f4; }
body { display: flex; }
#view { flex: 1; min-width: 0; height: 100%; display: block; }
#panel { width: 330px; height: 100%; overflow: auto; box-sizing: border-box; padding: 14px 16px; background: #fff; border-left: 1px solid #ddd; }
#panel h1 { font-size: 16px; margin: 0 0 10px; word-break: break-all; }
#panel h2 { font-size: 14px; margin: 14px 0 6px; }
#controls { display: flex; flex-wrap: wrap; gap: 6px 14px; margin-bottom: 10px; }
#controls select { width: 100%; }
#legend { display: flex; flex-wrap: wrap; gap: 4px 12px; margin-bottom: 12px; font-size: 12px; }
#legend .key i { display: inline-block; width: 10px; height: 10px; margin-right: 4px; border-radius: 2px; vertical-align: -1px; }
#report { border-collapse: collapse; width: 100%; }
#report th { text-align: left; font-weight: normal; color: #666; padding: 2px 8px 2px 0; vertical-align: top; }
#report td { padding: 2px 0; }
#warnings { padding-left: 18px; color: #9a3412; }
#error { position: fixed; left: 12px; top: 12px; right: 350px; padding: 10px; background: #fee; border: 1px solid #c00; }
footer { margin-top: 16px; font-size: 11px; color: #888; }
body.preview #panel { display: none; }
#caption, #views { display: none; }
body.preview #caption { display: block; position: fixed; left: 0; right: 0; top: 10px; text-align: center; font-size: 18px; }
body.preview #views { display: flex; position: fixed; left: 0; right: 0; bottom: 10px; color: #777; }
body.preview #views span { flex: 1; text-align: center; }
)css";

}  // namespace

std::string escape_html(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::vector<Segment> skeleton_segments(const Skeleton& skeleton) {
  std::vector<Segment> out;
  if (skeleton.node_count() < 2) return out;
  const modeling::ChainTree t = modeling::build_chains(skeleton);
  const auto& g = skeleton.graph;
  auto step = [&](NodeId v) { return (g[v].position - g[t.parent[v]].position).norm(); };
  // The longest path from each node down to a tip: chains children first, each from its tip end.
  std::vector<double> reach(skeleton.node_count(), 0.0);
  for (auto c = t.chains.rbegin(); c != t.chains.rend(); ++c)
    for (std::size_t k = c->nodes.size() - 1; k > 0; --k) {
      const NodeId v = c->nodes[k];
      reach[t.parent[v]] = std::max(reach[t.parent[v]], reach[v] + step(v));
    }
  // A chain keeps its fork's order if it leads the longest way on from there, else one more.
  std::vector<int> order(skeleton.node_count(), 0);
  for (const auto& c : t.chains) {
    const NodeId fork = c.nodes.front(), first = c.nodes[1];
    NodeId longest = first;
    for (NodeId sibling : t.children[fork])
      if (reach[sibling] + step(sibling) > reach[longest] + step(longest)) longest = sibling;
    const int o = order[fork] + (longest == first ? 0 : 1);
    for (std::size_t k = 1; k < c.nodes.size(); ++k) {
      const NodeId v = c.nodes[k], p = c.nodes[k - 1];
      order[v] = o;
      out.push_back({g[p].position + skeleton.offset, g[v].position + skeleton.offset, o, 0.5 * (g[p].radius + g[v].radius)});
    }
  }
  return out;
}

std::vector<PointClass> point_classes(const PointCloud& cloud, const Skeleton& skeleton) {
  std::vector<PointClass> out(cloud.size(), PointClass::left_out);
  for (NodeId v = 0; v < skeleton.node_count(); ++v)
    for (std::uint32_t i : skeleton[v].points)
      if (i < out.size()) out[i] = PointClass::tree;
  return out;
}

std::string html_page(const Scene& scene, const HtmlOptions& options) {
  if (detail::kViewerScript.empty()) throw Error("this build of treeskel has no viewer script");
  const Eigen::Vector3d centre = scene_centre(scene);
  Payload payload;
  // The box of everything, around the centre, that positions are quantized across.
  Eigen::AlignedBox3d box;
  auto extend = [&](const std::vector<float>& xyz) {
    for (std::size_t i = 0; i + 2 < xyz.size(); i += 3) box.extend(Eigen::Vector3d(xyz[i], xyz[i + 1], xyz[i + 2]));
  };
  std::size_t shown = 0;
  std::vector<float> cloud_points, segment_ends, mesh_vertices;
  if (scene.cloud && !scene.cloud->empty()) {
    const std::size_t n = scene.cloud->size();
    const std::size_t keep = std::min(n, std::max<std::size_t>(options.max_points, 1));
    std::vector<float> points;
    std::vector<std::uint8_t> classes;
    points.reserve(3 * keep);
    classes.reserve(keep);
    for (std::size_t k = 0; k < keep; ++k) {
      const std::size_t i = keep == n ? k : static_cast<std::size_t>((static_cast<unsigned long long>(k) * n) / keep);
      push(points, scene.cloud->positions[i] + scene.cloud->offset - centre);
      classes.push_back(static_cast<std::uint8_t>(i < scene.classes.size() ? scene.classes[i] : PointClass::tree));
    }
    shown = keep;
    extend(points);
    cloud_points = std::move(points);
    payload.add("classes", classes);
  }
  if (!scene.skeleton.empty()) {
    std::vector<float> ends, radii;
    std::vector<std::uint8_t> orders;
    for (const auto& s : scene.skeleton) {
      push(ends, s.a - centre);
      push(ends, s.b - centre);
      radii.push_back(static_cast<float>(s.radius));
      orders.push_back(static_cast<std::uint8_t>(std::clamp(s.order, 0, 255)));
    }
    extend(ends);
    segment_ends = std::move(ends);
    payload.add("segment_radii", radii);
    payload.add("segment_orders", orders);
  }
  if (scene.mesh && scene.mesh->n_faces() > 0) {
    const auto& m = *scene.mesh;
    std::vector<float> vertices;
    vertices.reserve(3 * m.n_vertices());
    for (auto v : m.vertices()) {
      const auto p = m.point(v);
      push(vertices, Eigen::Vector3d(p[0], p[1], p[2]) + scene.mesh_offset - centre);
    }
    std::vector<std::uint32_t> triangles;
    triangles.reserve(3 * m.n_faces());
    for (auto f : m.faces())
      for (auto v : m.fv_range(f)) triangles.push_back(static_cast<std::uint32_t>(v.idx()));
    extend(vertices);
    mesh_vertices = std::move(vertices);
    payload.add("triangles", triangles);
  }
  if (!box.isEmpty()) {
    if (!cloud_points.empty()) payload.add_quantized("points", cloud_points, box);
    if (!segment_ends.empty()) payload.add_quantized("segments", segment_ends, box);
    if (!mesh_vertices.empty()) payload.add_quantized("vertices", mesh_vertices, box);
  }
  nlohmann::ordered_json manifest;
  manifest["title"] = scene.title;
  manifest["up"] = {scene.up.x(), scene.up.y(), scene.up.z()};
  manifest["centre"] = {centre.x(), centre.y(), centre.z()};
  manifest["shown_points"] = shown;
  manifest["compressed"] = true;
  manifest["arrays"] = payload.manifest();
  manifest["report"] = scene.report;

  std::ostringstream page;
  page << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
       << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
       << "<meta name=\"generator\" content=\"treeskel\">\n"
       << "<title>" << escape_html(scene.title) << " - treeskel</title>\n<style>" << kStyle << "</style>\n</head>\n<body>\n"
       << "<canvas id=\"view\"></canvas>\n"
       << "<aside id=\"panel\"><h1 id=\"title\"></h1><div id=\"controls\"></div><div id=\"legend\"></div><div id=\"details\"></div>"
       << "<footer>Distances in the input's units. Drag to turn, scroll to zoom, right-drag to move. "
       << "Made by treeskel with three.js " << detail::kThreeVersion << " (MIT licence, in this page's script).</footer></aside>\n"
       << "<div id=\"error\" hidden></div><div id=\"caption\"></div><div id=\"views\"><span>side</span><span>from above</span></div>\n"
       << "<script type=\"application/json\" id=\"treeskel-scene\">" << script_json(manifest) << "</script>\n"
       << "<script type=\"application/octet-stream\" id=\"treeskel-data\">\n" << base64(deflate(payload.bytes()))
       << "\n</script>\n<script>\n" << detail::kViewerScript << "\n</script>\n</body>\n</html>\n";
  return page.str();
}

void write_html(const fs::path& path, const Scene& scene, const HtmlOptions& options) {
  const std::string page = html_page(scene, options);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(page.data(), static_cast<std::streamsize>(page.size()));
  out.close();
  if (!out) throw Error(path.string() + ": cannot write the page: " + std::strerror(errno));
}

std::string find_chromium() {
  if (const char* chosen = std::getenv("TREESKEL_CHROMIUM"); chosen && *chosen)
    return ::access(chosen, X_OK) == 0 ? chosen : "";
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "/usr/bin:/bin");
  std::string dir;
  std::vector<std::string> folders;
  while (std::getline(dirs, dir, ':'))
    if (!dir.empty()) folders.push_back(dir);
  for (const char* name : {"chromium", "chromium-browser", "google-chrome", "google-chrome-stable"})
    for (const auto& d : folders) {
      const fs::path candidate = fs::path(d) / name;
      if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
    }
  return "";
}

void render_preview(const fs::path& html, const fs::path& png, int width, int height) {
  const std::string chromium = find_chromium();
  if (chromium.empty())
    throw Error("a preview needs Chromium (apt-get install chromium, or set TREESKEL_CHROMIUM to a Chrome or Chromium)");
  std::string folder_name = (fs::temp_directory_path() / "treeskel-preview-XXXXXX").string();
  if (!::mkdtemp(folder_name.data())) throw Error(std::string("cannot make a temporary folder for the preview: ") + std::strerror(errno));
  const fs::path folder = folder_name;
  struct Cleanup {
    fs::path p;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(p, ec);
    }
  } cleanup{folder};
  const fs::path shot = folder / "preview.png";
  const std::string url = "file://" + fs::absolute(html).string() + "#preview";
  // Software WebGL (SwiftShader), no sandbox (root in containers), a private profile; the virtual
  // time budget lets the page decode its data and draw before the shot is taken.
  const io::ProgramResult run = io::run_program(
      {chromium, "--headless", "--no-sandbox", "--disable-gpu-sandbox", "--use-angle=swiftshader",
       "--enable-unsafe-swiftshader", "--hide-scrollbars", "--mute-audio", "--no-first-run",
       "--disable-extensions", "--user-data-dir=" + (folder / "profile").string(),
       "--window-size=" + std::to_string(width) + "," + std::to_string(height), "--virtual-time-budget=30000",
       "--screenshot=" + shot.string(), url},
      folder / "log");
  if (!run.started) throw Error("cannot start " + chromium + ": " + run.error);
  if (!run.ok() || !fs::exists(shot) || fs::file_size(shot) == 0)
    throw Error("Chromium could not render the preview (" + io::last_line_of(folder / "log") + ")");
  std::error_code ec;
  fs::rename(shot, png, ec);
  if (ec) {
    fs::copy_file(shot, png, fs::copy_options::overwrite_existing, ec);
    if (ec) throw Error(png.string() + ": cannot write the preview: " + ec.message());
  }
}

}  // namespace treeskel::view
