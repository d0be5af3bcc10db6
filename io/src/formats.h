// Per-format readers and writers behind the point_cloud_io facade. Readers return world coordinates
// (offset zero); the facade moves them to the local frame.
#pragma once

#include "treeskel/io/point_cloud_io.h"
#include "treeskel/point_cloud.h"
#include "treeskel/skeleton.h"

#include <filesystem>
#include <iosfwd>
#include <string>
#include <string_view>

namespace treeskel::io::detail {

PointCloud read_xyz(std::string_view data, const std::string& name);
PointCloud read_ply(std::string_view data, const std::string& name);
PointCloud read_las(std::string_view data, const std::string& name);
/// LAZ, decompressed by laz-perf under Node.js (laz.cpp); `head` is the file's bytes (an uncompressed
/// file named .laz is read as LAS).
PointCloud read_laz(const std::filesystem::path& path, std::string_view head, const std::string& name);

/// Skeleton readers (skeleton_io.cpp): nodes carry no point lists; the root as stored, else 0 (JSON)
/// or the lowest node along z (PLY).
Skeleton read_skeleton_json(std::string_view data, const std::string& name);
Skeleton read_skeleton_ply(std::string_view data, const std::string& name);

void write_xyz(std::ostream& out, const PointCloud& cloud);
void write_ply(std::ostream& out, const PointCloud& cloud, bool binary, const std::vector<PointField>& fields = {});
/// LAS 1.2 (point format 0, or 2 with colours); LAS 1.4 with an extra bytes VLR when `fields` are given.
void write_las(std::ostream& out, const PointCloud& cloud, const std::vector<PointField>& fields = {});

/// Appends the shortest decimal text that reads back to exactly `value`.
void append_number(std::string& out, double value);
/// Appends point i as one text line: world x y z, then nx ny nz and red green blue where present.
void append_point_line(std::string& out, const PointCloud& cloud, std::size_t i);
/// Parses a whole token as a number ("+1.5", "1e-3", "nan" accepted; "1.5x" refused).
bool parse_number(std::string_view token, double& value);

}  // namespace treeskel::io::detail
