// The triangles of one attempt of the sweep (see attempt.h), from where the rings were laid: each
// join's surface (the convex hull of its rings and extra points, less the rings' own faces), each
// tube's bands between two rings, the base's flat cap and each tip's cone. Every face is given its
// part and owner, so that crossings can be found between parts and thinned by branch.
#pragma once

#include "attempt.h"
#include "tube.h"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <map>
#include <optional>
#include <utility>
#include <vector>

namespace treeskel::modeling::detail {

/// Convex hulls of join points already computed: the points' coordinates, and the hull's triangles
/// as positions in that list (none when some point was not on the hull). Repair rounds leave most
/// joins as they were: their hulls are computed once.
using HullCache = std::map<std::vector<double>, std::optional<std::vector<std::array<std::size_t, 3>>>>;

/// A tube's rings, from the first (at a join or the base) to the last (at a join or before the tip).
struct Tube {
  NodeId owner = 0;  ///< the first node of its branch's chain, which a crossing thins
  std::vector<Ring> rings;
  bool base = false, tip = false;  ///< first ring capped flat; last ring closed by a cone
  std::size_t first_vertex = 0, last_vertex = 0;  ///< join ring vertices (when not base / tip)
  std::ptrdiff_t start_join = -1, end_join = -1;  ///< index of the join at either end
  double apex_height = 0.0;  ///< of the tip's cone, along the last ring's normal
  Eigen::Vector3d base_centre = Eigen::Vector3d::Zero();  ///< the base cap's centre (the first ring's: flat)
};

/// A join's rings (one per arm) and the vertices they were given.
struct Join {
  std::vector<Ring> rings;
  std::vector<std::size_t> first_vertex;
  /// Points of the hull besides the rings' (a cone's apex where one arm is left; the root's base),
  /// with their vertex ids; the last `optional` of them may be left inside it.
  std::vector<std::pair<Eigen::Vector3d, std::size_t>> points;
  std::size_t optional = 0;
  NodeId top = 0;       ///< the node a join that does not fit asks to thin
  double radius = 0.0;  ///< its thickest branch's
};

/// Appends `ring`'s vertices to `vertices`; returns the index of its first.
std::size_t add_ring(std::vector<Eigen::Vector3d>& vertices, const Ring& ring);

/// Adds the faces of `joins` and `tubes` to `attempt`, whose vertices already hold the join rings'
/// (the ids in `Join::first_vertex`, `Tube::first_vertex` and `last_vertex`); the tubes' other rings,
/// caps and apexes are added. Each join is a part, and each band, cap and cone of a tube is one, with
/// the rings it touches and its axis (see `Attempt`). A join whose hull leaves a required point
/// inside (the rings do not fit) adds no face and puts its `top` in `attempt.shrink`.
void tessellate(const std::vector<Join>& joins, const std::vector<Tube>& tubes, HullCache& hulls, Attempt& attempt);

}  // namespace treeskel::modeling::detail
