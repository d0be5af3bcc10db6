// Example 1: read a cloud, extract its skeleton with the default options, walk the tree from the root
// and write the skeleton as PLY.
//
//   01_skeletonize [CLOUD [SKELETON.ply]]   (default: the bundled tree, skeleton.ply)
#include "treeskel/error.h"
#include "treeskel/io/point_cloud_io.h"
#include "treeskel/io/skeleton_io.h"
#include "treeskel/pipeline.h"

#include <iostream>

int main(int argc, char** argv) {
  const std::string input = argc > 1 ? argv[1] : TREESKEL_DATA_DIR "/tree_rtwig.txt";
  const std::string output = argc > 2 ? argv[2] : "skeleton.ply";
  try {
    const treeskel::PointCloud cloud = treeskel::io::read_point_cloud(input);

    treeskel::SkeletonOptions options;  // every default follows the cloud's scale
    options.root.up = Eigen::Vector3d::UnitZ();
    treeskel::SkeletonStats stats;
    const treeskel::Skeleton skeleton = treeskel::extract_skeleton(cloud, options, &stats);

    // The skeleton is a Boost.Graph adjacency list: walk it from its root.
    std::size_t tips = 0;
    for (auto v : treeskel::bfs_order(skeleton.graph, skeleton.root))
      if (v != skeleton.root && boost::degree(v, skeleton.graph) == 1) ++tips;
    const Eigen::Vector3d base = skeleton[skeleton.root].position + skeleton.offset;
    std::cout << input << ": " << cloud.size() << " points, octree depth " << stats.octree_depth << ", "
              << skeleton.node_count() << " nodes, " << tips << " twig tips, root at " << base.transpose()
              << ", first node above the root at "
              << (skeleton[*boost::adjacent_vertices(skeleton.root, skeleton.graph).first].position + skeleton.offset).transpose()
              << "\n";
    treeskel::io::write_skeleton(output, skeleton);
    std::cout << "wrote " << output << "\n";
  } catch (const treeskel::Error& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
