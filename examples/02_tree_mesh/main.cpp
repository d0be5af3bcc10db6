// Example 2: from a cloud to a tree model: skeleton, radii by the pipe model, one watertight mesh,
// its checks and the tree's measurements, written as GLB.
//
//   02_tree_mesh [CLOUD [MODEL.glb]]   (default: the bundled tree, tree.glb)
#include "treeskel/error.h"
#include "treeskel/io/mesh_io.h"
#include "treeskel/io/point_cloud_io.h"
#include "treeskel/modeling/measurements.h"
#include "treeskel/modeling/radii.h"
#include "treeskel/modeling/sweep.h"
#include "treeskel/pipeline.h"

#include <iostream>

int main(int argc, char** argv) {
  const std::string input = argc > 1 ? argv[1] : TREESKEL_DATA_DIR "/tree_rtwig.txt";
  const std::string output = argc > 2 ? argv[2] : "tree.glb";
  try {
    const treeskel::PointCloud cloud = treeskel::io::read_point_cloud(input);
    treeskel::Skeleton skeleton = treeskel::extract_skeleton(cloud);

    // Radii: circle fits on each node's points, made to obey Leonardo's rule (r^2 = sum of the
    // children's r^2 at every fork) and to never grow toward the tips.
    treeskel::modeling::fit_radii(skeleton, &cloud);

    // One closed, manifold mesh of the wood; the report says what the sweep had to give up.
    treeskel::modeling::SweepStats stats;
    const treeskel::modeling::TreeMesh mesh = treeskel::modeling::sweep_mesh(skeleton, {}, &stats);
    const treeskel::modeling::MeshCheck check = treeskel::modeling::check_mesh(mesh);
    if (!check.ok()) {
      std::cerr << "the mesh failed its check: " << check.problem() << '\n';
      return 1;
    }

    const treeskel::modeling::TreeMeasurements m = treeskel::modeling::measure_tree(skeleton, &cloud);
    treeskel::io::write_mesh(output, mesh, skeleton.offset);
    std::cout << input << ": " << mesh.n_faces() << " triangles, volume " << check.volume << " (frustums: " << m.volume
              << "), height " << m.height << ", DBH " << (m.dbh ? std::to_string(*m.dbh) : std::string("n/a")) << ", "
              << m.cylinders.size() << " QSM cylinders, " << stats.twigs_absorbed << " twigs inside fork joins -> "
              << output << '\n';
  } catch (const treeskel::Error& e) {
    std::cerr << "02_tree_mesh: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
