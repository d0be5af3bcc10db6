// The fixture test `bundled_skeletons`: extracts the skeletons of the named bundled clouds once per
// ctest run into DIR, for the tests that sweep them (see support/bundled.h).
// Usage: treeskel_write_fixtures DIR CLOUD...
#include "support/bundled.h"

#include <exception>
#include <filesystem>
#include <iostream>

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: treeskel_write_fixtures DIR CLOUD...\n";
    return 2;
  }
  try {
    std::filesystem::create_directories(argv[1]);
    for (int i = 2; i < argc; ++i) {
      const treeskel::Skeleton s = treeskel::test::extract_bundled_skeleton(argv[i]);
      const std::string path = std::string(argv[1]) + "/" + argv[i] + ".skeleton";
      treeskel::test::save_skeleton_fixture(path, s);
      // What the tests will load must be what was extracted.
      const treeskel::Skeleton back = treeskel::test::load_skeleton_fixture(path);
      bool same = back.node_count() == s.node_count() && back.edge_count() == s.edge_count() && back.root == s.root &&
                  back.offset == s.offset;
      for (treeskel::NodeId v = 0; same && v < s.node_count(); ++v)
        same = back[v].position == s[v].position && back[v].radius == s[v].radius;
      if (!same) {
        std::cerr << path << ": does not read back exactly\n";
        return 1;
      }
      std::cout << path << ": " << s.node_count() << " nodes\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "treeskel_write_fixtures: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
