/// @file tree_generator.h
/// Random, botanically plausible trees made of tapered cylinders: a bending trunk whose branches leave
/// at 30-60 degrees, several orders deep, with radii that follow the pipe model (the cross section
/// below a fork equals the sum of those above). Used for speed benchmarks and tests of scale.
#pragma once

#include "treeskel/eval/cylinders.h"

#include <cstdint>
#include <vector>

namespace treeskel::eval {

struct GrowOptions {
  std::uint64_t seed = 1;
  int orders = 3;               ///< branching orders above the trunk
  int branches = 5;             ///< side branches on the trunk; each order has 0.7 times as many
  double height = 10.0;         ///< trunk length
  double trunk_radius = 0.2;    ///< radius at the base
  double length_ratio = 0.55;   ///< length of a side branch relative to its parent
  double segment_length = 0.25; ///< branches are polylines of segments about this long (times the order's scale)
  double bend = 0.08;           ///< random turn per segment, radians
};

/// A grown tree: its cylinders and, for each, the cylinder it grows from (-1 for the trunk base).
struct GrownTree {
  std::vector<Cylinder> cylinders;
  std::vector<int> parent;
};

GrownTree grow_tree(const GrowOptions& options = {});

}  // namespace treeskel::eval
