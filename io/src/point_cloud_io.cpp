#include "treeskel/io/point_cloud_io.h"

#include "formats.h"
#include "input_file.h"
#include "treeskel/error.h"
#include "treeskel/io/atomic_file.h"

#include <algorithm>
#include <ostream>

namespace treeskel::io {

namespace {

const std::vector<std::string> text_extensions{"xyz", "txt", "asc", "csv", "pts"};

bool is_text(const std::string& ext) {
  return std::find(text_extensions.begin(), text_extensions.end(), ext) != text_extensions.end();
}

/// The extensions read (or, `writing`, written: not .laz), as a list for messages.
std::string known_list(bool writing = false) {
  std::string s;
  for (const auto& e : point_cloud_extensions())
    if (!writing || e != "laz") s += (s.empty() ? "." : ", .") + e;
  return s;
}

}  // namespace

const std::vector<std::string>& point_cloud_extensions() {
  static const std::vector<std::string> all{"xyz", "txt", "asc", "csv", "pts", "ply", "las", "laz"};
  return all;
}

PointCloud read_point_cloud(const std::filesystem::path& path) {
  const std::string name = path.string();
  const std::string ext = extension_of(path);
  if (ext != "ply" && ext != "las" && ext != "laz" && !is_text(ext))
    throw InputError(name + ": unknown point cloud extension '." + ext + "'; treeskel reads " + known_list());
  const detail::InputFile file(path);
  const std::string_view data = file.bytes();
  if (data.empty()) throw InputError(name + ": the file is empty");
  PointCloud cloud = ext == "ply"   ? detail::read_ply(data, name)
                     : ext == "las" ? detail::read_las(data, name)
                     : ext == "laz" ? detail::read_laz(path, data, name)
                                    : detail::read_xyz(data, name);
  recentre_offset(cloud);
  return cloud;
}

void write_point_cloud(const std::filesystem::path& path, const PointCloud& cloud, const CloudWriteOptions& options) {
  const std::string ext = extension_of(path);
  if (ext != "ply" && ext != "las" && !is_text(ext))
    throw Error(path.string() + ": unknown point cloud extension '." + ext + "'; treeskel writes " + known_list());
  if (!options.fields.empty() && ext != "ply" && ext != "las")
    throw Error(path.string() + ": per-point fields (" + options.fields.front().name + ") are written to PLY and LAS only");
  for (const auto& f : options.fields)
    TREESKEL_REQUIRE(f.values.size() == cloud.size(), "a field value per point");
  write_atomically(path, [&](std::ostream& out) {
    if (ext == "ply") detail::write_ply(out, cloud, options.ply_binary, options.fields);
    else if (ext == "las") detail::write_las(out, cloud, options.fields);
    else detail::write_xyz(out, cloud);
  });
}

}  // namespace treeskel::io
