#include "modeling/model_fixtures.h"
#include "support/synthetic.h"
#include "treeskel/error.h"
#include "treeskel/io/atomic_file.h"
#include "treeskel/io/mesh_io.h"
#include "treeskel/modeling/measurements.h"
#include "treeskel/modeling/sweep.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>

#include <algorithm>
#include <array>
#include <cstring>
#include <filesystem>
#include <vector>

namespace treeskel::io {
namespace {

namespace fs = std::filesystem;

TEST(MeshIo, EveryFormatReadsBackWithTheSameCounts) {
  const Skeleton s = test::y_shape(0.05, 0.6, 10);
  const modeling::TreeMesh mesh = modeling::sweep_mesh(s);
  test::TempDir dir;
  for (const char* ext : {"obj", "gltf", "glb", "ply", "stl"}) {
    const std::string path = dir.path(std::string("tree.") + ext);
    write_mesh(path, mesh, Eigen::Vector3d(10, 20, 30));
    const modeling::TreeMesh back = read_mesh(path);
    SCOPED_TRACE(ext);
    EXPECT_EQ(back.n_vertices(), mesh.n_vertices());
    EXPECT_EQ(back.n_faces(), mesh.n_faces());
    EXPECT_TRUE(modeling::check_mesh(back, false).boundary_edges == 0);
    // The offset goes out with the points; glTF is read back as a viewer shows it, Y up.
    const int up = std::string(ext).rfind("gl", 0) == 0 ? 1 : 2;
    double min_in = 1e300, min_out = 1e300;
    for (auto v : mesh.vertices()) min_in = std::min(min_in, mesh.point(v)[2]);
    for (auto v : back.vertices()) min_out = std::min(min_out, back.point(v)[up]);
    EXPECT_NEAR(min_out, min_in + 30.0, 1e-4);
  }
  // The buffer the .gltf names is beside it (assimp names it after the file, "tree.bin" or "tree_0.bin").
  const auto gltf = nlohmann::json::parse(read_whole_file(dir.path("tree.gltf")));
  const std::string bin = gltf.at("buffers").at(0).at("uri").get<std::string>();
  EXPECT_EQ(bin.rfind("tree", 0), 0u) << bin;
  EXPECT_TRUE(fs::exists(dir.path(bin))) << bin;
  // Nothing else was left behind (no temporary folders, no material file).
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir.root())) {
    (void)e;
    ++files;
  }
  EXPECT_EQ(files, 6u);
}

// A georeferenced tree: OBJ keeps every coordinate in double precision, glTF keeps local vertices
// and the exact offset in its root node (with the turn to Y up), PLY falls back to local coordinates.
// assimp 5.2 skips a line end right after a binary PLY's header: a first vertex whose x starts
// (little-endian) with the byte '\n' made the whole file read one byte off. The writer puts a
// vertex with a safe first byte first, and the mesh reads back the same.
TEST(MeshIo, PlyWhoseFirstByteWouldBeALineEndReadsBack) {
  const Skeleton s = test::y_shape(0.05, 0.6, 10);
  modeling::TreeMesh mesh = modeling::sweep_mesh(s);
  for (unsigned char bad : {'\n', '\r', '\0'}) {
    // Vertex 0's x with its lowest byte set to `bad`.
    auto p = mesh.point(mesh.vertex_handle(0));
    float x = static_cast<float>(p[0]);
    unsigned char bytes[4];
    std::memcpy(bytes, &x, 4);
    bytes[0] = bad;
    std::memcpy(&x, bytes, 4);
    p[0] = x;
    mesh.set_point(mesh.vertex_handle(0), p);
    test::TempDir dir;
    write_mesh(dir.path("tree.ply"), mesh, Eigen::Vector3d::Zero());
    const modeling::TreeMesh back = read_mesh(dir.path("tree.ply"));
    SCOPED_TRACE(static_cast<int>(bad));
    ASSERT_EQ(back.n_vertices(), mesh.n_vertices());
    EXPECT_EQ(back.n_faces(), mesh.n_faces());
    auto sorted_points = [](const modeling::TreeMesh& m) {
      std::vector<std::array<float, 3>> out;
      for (auto v : m.vertices())
        out.push_back({static_cast<float>(m.point(v)[0]), static_cast<float>(m.point(v)[1]), static_cast<float>(m.point(v)[2])});
      std::sort(out.begin(), out.end());
      return out;
    };
    EXPECT_EQ(sorted_points(back), sorted_points(mesh));
    EXPECT_NEAR(modeling::check_mesh(back, false).volume, modeling::check_mesh(mesh, false).volume,
                1e-6 * modeling::check_mesh(mesh, false).volume);
  }
}

TEST(MeshIo, GeoreferencedMeshesKeepMillimetres) {
  const Skeleton s = test::y_shape(0.05, 0.6, 10);
  const modeling::TreeMesh mesh = modeling::sweep_mesh(s);
  const Eigen::Vector3d offset(269656.1863, 5168602.6421, 110.2612);
  test::TempDir dir;
  MeshFrame frame;
  frame.offset = offset;

  const MeshPlacement obj = write_mesh(dir.path("t.obj"), mesh, frame);
  EXPECT_TRUE(obj.note.empty());
  std::ifstream in(dir.path("t.obj"));
  std::string tag;
  std::size_t i = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("v ", 0) != 0) continue;
    std::istringstream v(line.substr(2));
    Eigen::Vector3d p;
    v >> p.x() >> p.y() >> p.z();
    const auto q = mesh.point(modeling::TreeMesh::VertexHandle(static_cast<int>(i++)));
    EXPECT_LT((p - (Eigen::Vector3d(q[0], q[1], q[2]) + offset)).norm(), 1e-6);
  }
  EXPECT_EQ(i, mesh.n_vertices());

  const MeshPlacement glb = write_mesh(dir.path("t.gltf"), mesh, frame);
  EXPECT_TRUE(glb.y_up_rotation);
  const auto doc = nlohmann::json::parse(read_whole_file(dir.path("t.gltf")));
  const auto m = doc["nodes"][0]["matrix"].get<std::vector<double>>();
  // Z up turned to Y up: (x, y, z) -> (x, z, -y), the offset turned the same way, exactly.
  EXPECT_EQ(m[12], offset.x());
  EXPECT_EQ(m[13], offset.z());
  EXPECT_EQ(m[14], -offset.y());
  EXPECT_EQ(m[0], 1.0);
  EXPECT_EQ(m[6], -1.0);  // column 1 (y) goes to -z
  EXPECT_EQ(m[9], 1.0);   // column 2 (z) goes to +y

  // Read back as a reader meets them: every vertex apart (32-bit floats at UTM coordinates are
  // centimetres apart, and joined distinct vertices of the files before), closed and manifold; the
  // OBJ in the input's frame to the micrometre.
  write_mesh(dir.path("t.glb"), mesh, frame);
  for (const char* name : {"t.obj", "t.gltf", "t.glb"}) {
    const modeling::TreeMesh back = read_mesh(dir.path(name));
    EXPECT_EQ(back.n_vertices(), mesh.n_vertices()) << name;
    const modeling::MeshCheck check = modeling::check_mesh(back, false);
    EXPECT_EQ(check.boundary_edges, 0u) << name;
    EXPECT_EQ(check.non_manifold_vertices, 0u) << name;
  }
  const modeling::TreeMesh obj_back = read_mesh(dir.path("t.obj"));
  for (auto v : obj_back.vertices()) {
    const auto p = obj_back.point(v), q = mesh.point(v);
    EXPECT_LT((Eigen::Vector3d(p[0], p[1], p[2]) - Eigen::Vector3d(q[0], q[1], q[2]) - offset).norm(), 1e-6);
  }

  const MeshPlacement ply = write_mesh(dir.path("t.ply"), mesh, frame);
  EXPECT_FALSE(ply.note.empty());
  EXPECT_EQ(ply.left_out, offset);
  const modeling::TreeMesh back = read_mesh(dir.path("t.ply"));
  EXPECT_EQ(back.n_vertices(), mesh.n_vertices());
  EXPECT_TRUE(modeling::check_mesh(back, false).boundary_edges == 0);
}

TEST(MeshIo, GltfOfAZUpTreeIsTallestAlongY) {
  const modeling::TreeMesh mesh = modeling::sweep_mesh(test::straight(3.0, 0.1, 10));
  test::TempDir dir;
  write_mesh(dir.path("t.glb"), mesh, Eigen::Vector3d(5, 6, 7));
  const modeling::TreeMesh back = read_mesh(dir.path("t.glb"));
  Eigen::AlignedBox3d box;
  for (auto v : back.vertices()) box.extend(Eigen::Vector3d(back.point(v)[0], back.point(v)[1], back.point(v)[2]));
  EXPECT_NEAR(box.sizes().y(), 3.0, 0.06);
  EXPECT_LT(box.sizes().x(), 0.3);
  EXPECT_LT(box.sizes().z(), 0.3);
  EXPECT_NEAR(box.min().y(), 7.0, 1e-4);  // the base at the offset's height
}

TEST(MeshIo, SkeletonLinesGoBesideTheMesh) {
  const Skeleton s = test::y_shape(0.05, 0.6, 10);
  const modeling::TreeMesh mesh = modeling::sweep_mesh(s);
  test::TempDir dir;
  write_mesh(dir.path("tree.glb"), mesh, Eigen::Vector3d::Zero(), &s);
  const modeling::TreeMesh back = read_mesh(dir.path("tree.glb"));  // lines skipped
  EXPECT_EQ(back.n_faces(), mesh.n_faces());
  EXPECT_GT(fs::file_size(dir.path("tree.glb")), 0u);
}

TEST(MeshIo, UnknownExtensionWritesNothing) {
  const modeling::TreeMesh mesh = modeling::sweep_mesh(test::straight(1.0, 0.1, 4));
  test::TempDir dir;
  EXPECT_FALSE(is_mesh_extension("tree.fbx"));
  EXPECT_TRUE(is_mesh_extension("tree.GLB"));
  EXPECT_THROW(write_mesh(dir.path("tree.fbx"), mesh, Eigen::Vector3d::Zero()), OptionError);
  EXPECT_TRUE(fs::is_empty(dir.root()));
  EXPECT_THROW(write_mesh(dir.path("missing/tree.obj"), mesh, Eigen::Vector3d::Zero()), Error);
  EXPECT_THROW(write_mesh(dir.path("empty.obj"), modeling::TreeMesh{}, Eigen::Vector3d::Zero()), InputError);
  EXPECT_TRUE(fs::is_empty(dir.root()));
  EXPECT_THROW(read_mesh(dir.path("none.obj")), InputError);
}

TEST(MeshIo, QsmTableHasTheHeaderAndOneRowPerCylinder) {
  const Skeleton s = test::y_shape(0.05, 0.6, 5);
  const auto m = modeling::measure_tree(s, nullptr);
  test::TempDir dir;
  write_qsm_csv(dir.path("qsm.csv"), m);
  const std::string text = read_whole_file(dir.path("qsm.csv"));
  EXPECT_EQ(text.substr(0, text.find('\n')),
            "id,parent,branch,order,position_in_branch,start_x,start_y,start_z,axis_x,axis_y,axis_z,length,radius");
  EXPECT_EQ(static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')), m.cylinders.size() + 1);
  EXPECT_NE(text.find("\n1,0,1,0,1,0,0,0,0,0,1,"), std::string::npos);
}

}  // namespace
}  // namespace treeskel::io
