/// @file skeleton_io.h
/// Writing and reading skeletons, by file extension, in the input cloud's frame:
///   .ply   `element vertex` with x y z radius (double), `element edge` with vertex1 vertex2 — the
///          layout MeshLab and CloudCompare read; the root is kept in a `comment root N` line
///   .obj   polylines: `v x y z` and `l a b`
///   .json  {"root", "nodes": [{"id", "position", "radius", "points"}], "edges": [[a, b]]}
#pragma once

#include "treeskel/skeleton.h"

#include <filesystem>
#include <string>

namespace treeskel::io {

/// True if `write_skeleton` knows the extension of `path` (.ply .obj .json).
bool is_skeleton_extension(const std::filesystem::path& path);

/// Writes the skeleton atomically. @throws Error for an unknown extension or a failed write.
void write_skeleton(const std::filesystem::path& path, const Skeleton& skeleton);

/// The skeleton as JSON text (the .json layout above).
std::string skeleton_to_json(const Skeleton& skeleton);

/// Reads a skeleton written as .ply or .json (nodes carry no point lists). Without a stored root, the
/// lowest node along z is the root. @throws InputError naming the file.
Skeleton read_skeleton(const std::filesystem::path& path);

}  // namespace treeskel::io
