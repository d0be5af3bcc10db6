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

/// Reads a skeleton written as .ply (ascii or binary) or .json (nodes carry no point lists). Without a stored root, the
/// lowest node along z is the root. @throws InputError naming the file.
Skeleton read_skeleton(const std::filesystem::path& path);

/// True if `path` holds a skeleton rather than a point cloud: a .json file, or a PLY (ascii or binary)
/// with no faces whose `edge` element (vertex1, vertex2) joins its vertices into a graph (at least one
/// edge for every two vertices); a cloud's PLY with a few edges, or a mesh, is a cloud.
/// @throws InputError if a .ply file is missing or its header is malformed.
bool looks_like_skeleton(const std::filesystem::path& path);

}  // namespace treeskel::io
