// The skeletons of the bundled clouds, radii fitted, shared by the tests that sweep them.
//
// ctest runs each test case as its own process, so an in-process cache would save nothing: the
// fixture test `bundled_skeletons` extracts them once per run into a folder (TREESKEL_TEST_FIXTURES,
// set by ctest for the tests that use them), in a text form that keeps every double exactly and the
// local frame as it is. Run outside ctest, a test extracts them itself: the same skeletons.
#pragma once

#include "treeskel/skeleton.h"

#include <string>

namespace treeskel::test {

/// The skeleton of the bundled cloud `name` (e.g. "tree_rtwig.txt"), default options, radii fitted
/// to the cloud. Node point lists are not kept. With "@whole-depths" after the name: the octree's
/// cells of whole depths only (`OctreeOptions::depth_steps` 1), far bridging of parts of ten points
/// or more and the limbs not straightened (`RadiusOptions::stiffness` 0): the skeleton some sweep
/// cases were found on.
Skeleton bundled_skeleton(const std::string& name);

/// Extracts the skeleton of the bundled cloud `name` (what bundled_skeleton returns without fixtures).
Skeleton extract_bundled_skeleton(const std::string& name);

/// Writes and reads the fixture form: the offset, the root, each node's local position and radius
/// (shortest exact decimals), the edges. @throws std::runtime_error on a file it cannot use.
void save_skeleton_fixture(const std::string& path, const Skeleton& skeleton);
Skeleton load_skeleton_fixture(const std::string& path);

}  // namespace treeskel::test
