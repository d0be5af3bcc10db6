/// @file mesh_io.h
/// Tree meshes out through assimp (.obj, .gltf, .glb, .ply, .stl), back in for checks, and the QSM
/// cylinder table as CSV.
#pragma once

#include "treeskel/modeling/measurements.h"
#include "treeskel/modeling/tree_mesh.h"
#include "treeskel/skeleton.h"

#include <Eigen/Core>

#include <filesystem>
#include <string>

namespace treeskel::io {

/// True if `write_mesh` knows the extension of `path` (.obj .gltf .glb .ply .stl).
bool is_mesh_extension(const std::filesystem::path& path);

/// Writes `mesh` (local frame, `offset` added on the way out) in the format named by the extension:
/// .obj (no material file), .gltf (with its .bin beside it) and .glb (glTF 2.0), .ply (binary),
/// .stl (binary). With `skeleton`, its edges go into the same file as a line primitive (glTF only
/// draws them; other formats keep them as a second mesh where they can). Files appear complete or
/// not at all. Coordinates are written as 32-bit floats, as these formats store them.
/// @throws OptionError for an unknown extension; Error when assimp fails.
void write_mesh(const std::filesystem::path& path, const modeling::TreeMesh& mesh, const Eigen::Vector3d& offset,
                const Skeleton* skeleton = nullptr);

/// Reads the triangles of a mesh file through assimp, identical vertices joined (STL stores none
/// shared). Lines and points are skipped.
/// @throws InputError naming the file when assimp cannot read it.
modeling::TreeMesh read_mesh(const std::filesystem::path& path);

/// Writes the cylinder table as CSV with a header line: id, parent, branch, order,
/// position_in_branch, start_x, start_y, start_z, axis_x, axis_y, axis_z, length, radius.
void write_qsm_csv(const std::filesystem::path& path, const modeling::TreeMeasurements& measurements);

}  // namespace treeskel::io
