/// @file point_cloud_io.h
/// Reading and writing point clouds, by file extension:
///   .xyz .txt .asc .csv .pts  text, one point a line (white space, comma or semicolon separated,
///                             '#' comments, CRLF accepted, extra columns ignored, optional header)
///   .ply                      ascii or binary (either endianness), float or double, with or without
///                             normals and colours
///   .las                      LAS 1.0 to 1.4, point formats 0 to 10
///   .laz                      the same compressed: decompressed by laz-perf (npm) under Node.js into a
///                             temporary LAS; the message says what is missing when either is
/// Clouds are moved to a local frame on reading (PointCloud::offset) and back on writing.
#pragma once

#include "treeskel/point_cloud.h"

#include <filesystem>
#include <string>
#include <vector>

namespace treeskel::io {

/// Reads a cloud. @throws InputError with the file name and, where it applies, the line or byte.
PointCloud read_point_cloud(const std::filesystem::path& path);

/// A value per point beside the position (a label, a height), written as a PLY property or as LAS
/// "extra bytes" (a LAS 1.4 file whose extra bytes VLR names each field and its type).
struct PointField {
  enum class Type { uint8, uint32, float32 };
  std::string name;
  Type type = Type::float32;
  std::vector<double> values;  ///< one per point, exact in `type`
};

struct CloudWriteOptions {
  bool ply_binary = true;  ///< binary little-endian PLY (else ascii)
  /// Properties after the position, normals and colours; PLY and LAS only (another format refuses them).
  std::vector<PointField> fields;
};

/// Writes a cloud in the format of the extension (.xyz .txt .asc .csv .pts .ply .las; not .laz), atomically.
/// @throws Error for an unknown extension or a failed write; no file is left behind.
void write_point_cloud(const std::filesystem::path& path, const PointCloud& cloud, const CloudWriteOptions& options = {});

/// The extensions read_point_cloud accepts.
const std::vector<std::string>& point_cloud_extensions();

}  // namespace treeskel::io
