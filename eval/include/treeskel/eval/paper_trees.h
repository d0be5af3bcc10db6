/// @file paper_trees.h
/// The synthetic ground-truth data set of Fu et al. 2020, section V.A: six tree skeletons with the
/// paper's complexity (branch points / endpoints 19/22, 11/13, 23/25, 65/87, 110/154, 58/89), grown
/// as plausible trees (a trunk, branches that leave at 25-55 degrees and bend, radii that taper and
/// obey Leonardo's rule at every fork), and the 72 point clouds of the paper's Table 1: three point
/// counts, three with missing data, three with noise and three with varying density per tree, all
/// normalised so that the longest side of the bounding box is 1. Deterministic for a seed.
#pragma once

#include "treeskel/eval/cylinders.h"
#include "treeskel/point_cloud.h"
#include "treeskel/skeleton.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace treeskel::eval {

/// What the paper says of one of its six trees.
struct PaperTreeSpec {
  int index;                            ///< 1 to 6
  int branch_points;                    ///< nodes of degree >= 3
  int endpoints;                        ///< nodes of degree 1 (the trunk base counts)
  std::array<std::size_t, 3> counts;    ///< the point counts of the "different number of points" clouds
};

/// The six trees, in the paper's order.
const std::array<PaperTreeSpec, 6>& paper_tree_specs();

/// A ground-truth tree: its skeleton (dense polyline nodes with radii, root at the trunk base) and
/// the cylinders whose surface the clouds are sampled on. Coordinates are normalised (longest side of
/// the bounding box of the wood is 1, minimum corner at the origin).
struct GroundTruth {
  Skeleton skeleton;
  std::vector<Cylinder> cylinders;
};

/// Grows tree `index` (1-6) with exactly the paper's counts of branch points and endpoints.
GroundTruth make_paper_tree(int index, std::uint64_t seed = 1);

/// How a tree is grown: its counts, and how its branches leave a fork. Forks grow one after the other
/// on the most vigorous (longest, with some disorder) open tip; the first child of a fork continues it
/// (the leader), the others leave it to the side. Angles in degrees from the parent's direction,
/// lengths as shares of the parent's length. The defaults are the paper trees' shape.
struct TreeShape {
  int branch_points = 19;                       ///< nodes of degree 3 or more
  int endpoints = 22;                           ///< nodes of degree 1, the trunk base included
  std::array<double, 2> leader_angle{4.0, 16.0};
  std::array<double, 2> side_angle{28.0, 52.0};
  std::array<double, 2> leader_length{0.78, 0.9};
  std::array<double, 2> side_length{0.62, 0.78};
  double lift = 0.2;       ///< side branches turn up: this much of +z is added to their direction
  int attempts = 40;       ///< directions tried per child, keeping the one farthest from other branches
  double clearance = 0.45; ///< a direction whose chord keeps this share of its length from others is taken at once
};

/// Grows a tree of `shape` from the random stream `seed`, normalised like the paper's trees.
/// @throws OptionError if the counts are impossible (endpoints must be 2 + branch points plus at most
/// two extra children per fork).
GroundTruth grow_truth(const TreeShape& shape, std::uint64_t seed);

/// The four degradations of the paper's Table 1.
enum class Degradation { points, missing, noise, vdensity };

/// One of the 72 clouds.
struct PaperCloud {
  std::string name;         ///< e.g. "tree1_14045", "tree4_missing_2" (the paper's names)
  int tree = 1;             ///< 1 to 6
  Degradation degradation = Degradation::points;
  int variant = 1;          ///< 1 to 3
  PointCloud cloud;         ///< in the ground truth's frame
};

/// The twelve clouds of one tree, in the paper's order (Table 1).
std::vector<PaperCloud> make_paper_clouds(const GroundTruth& truth, int index, std::uint64_t seed = 1);

/// Name of a degradation as in the paper's tables ("points", "missing", "noise", "vdensity").
std::string degradation_name(Degradation d);

}  // namespace treeskel::eval
