#include "modeling/model_fixtures.h"
#include "support/synthetic.h"
#include "treeskel/error.h"
#include "treeskel/io/atomic_file.h"
#include "treeskel/io/mesh_io.h"
#include "treeskel/modeling/measurements.h"
#include "treeskel/modeling/sweep.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

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
    // The offset goes out with the points.
    double min_in = 1e300, min_out = 1e300;
    for (auto v : mesh.vertices()) min_in = std::min(min_in, mesh.point(v)[2]);
    for (auto v : back.vertices()) min_out = std::min(min_out, back.point(v)[2]);
    EXPECT_NEAR(min_out, min_in + 30.0, 1e-4);
  }
  EXPECT_TRUE(fs::exists(dir.path("tree.bin")));  // beside the .gltf
  // Nothing else was left behind (no temporary folders, no material file).
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir.root())) {
    (void)e;
    ++files;
  }
  EXPECT_EQ(files, 6u);
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
