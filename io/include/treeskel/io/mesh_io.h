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

/// True if a mesh written to `path` holds the local frame's 32-bit floats whatever the frame asks
/// (glTF: local vertices under a root node that places them), so that the mesh's checks must be made
/// in those floats (`modeling::SweepOptions::local_floats`).
bool holds_local_floats(const std::filesystem::path& path);

/// Where a mesh file's coordinates are: the mesh is kept in a local frame (`world = local + offset`), so
/// that a georeferenced tree (x around 300,000, y around 5,000,000) keeps millimetres in 32-bit floats.
struct MeshFrame {
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  ///< added to the mesh's coordinates to get the input's frame
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();     ///< the input's up axis (glTF files turn it to +Y)
  bool local = false;                                ///< write local coordinates in every format
};

/// How `write_mesh` placed the coordinates, for reports.
struct MeshPlacement {
  /// Offset left out of the file's coordinates: add it to what the file holds (after any node
  /// transform of a glTF file, turned back to the input's up axis) to get the input's frame.
  Eigen::Vector3d left_out = Eigen::Vector3d::Zero();
  bool y_up_rotation = false;  ///< a glTF root node turns the input's up axis to +Y
  /// Why the offset was left out (empty when the file is in the input's frame).
  std::string note;
};

/// Writes `mesh` in the format named by the extension: .obj (no material file), .gltf (with its .bin
/// beside it) and .glb (glTF 2.0), .ply (binary), .stl (binary). With `skeleton`, its edges go into the
/// same file as lines (glTF draws them; other formats keep them as a second mesh where they can).
/// Files appear complete or not at all.
/// Frames: OBJ is text and holds every coordinate in double precision, in the input's frame. glTF
/// holds the local vertices (32-bit floats) and, in its root node, the rotation that turns the up
/// axis to +Y (glTF 2.0 is Y-up) and the offset as an exact translation. PLY and STL store 32-bit
/// floats only: they hold the input's frame when floats keep it to 1e-5 of the mesh's extent,
/// else local coordinates, and the returned placement says so. `frame.local` writes local coordinates
/// everywhere.
/// @throws OptionError for an unknown extension; Error when assimp fails.
MeshPlacement write_mesh(const std::filesystem::path& path, const modeling::TreeMesh& mesh, const MeshFrame& frame,
                         const Skeleton* skeleton = nullptr);

/// The same, with the up axis +Z and the offset as given.
MeshPlacement write_mesh(const std::filesystem::path& path, const modeling::TreeMesh& mesh,
                         const Eigen::Vector3d& offset, const Skeleton* skeleton = nullptr);

/// Reads the triangles of a mesh file, identical vertices joined (STL stores none shared): OBJ by
/// our own reader in double precision, the others through assimp with the node transforms applied
/// in double precision as a viewer applies them (a glTF file comes back Y-up, its vertices as the
/// file's 32-bit floats, its root node's translation as assimp reads it). Lines and points are skipped.
/// @throws InputError naming the file when assimp cannot read it.
modeling::TreeMesh read_mesh(const std::filesystem::path& path);

/// Writes the cylinder table as CSV with a header line: id, parent, branch, order,
/// position_in_branch, start_x, start_y, start_z, axis_x, axis_y, axis_z, length, radius.
void write_qsm_csv(const std::filesystem::path& path, const modeling::TreeMeasurements& measurements);

}  // namespace treeskel::io
