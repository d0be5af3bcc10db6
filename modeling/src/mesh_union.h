// The boolean union of closed tree meshes (CGAL Polygon Mesh Processing corefinement): how the
// sweep adds the limbs it swept apart (where a join or a crossing left no room) to the tree.
#pragma once

#include "treeskel/modeling/tree_mesh.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cstddef>
#include <memory>
#include <numeric>
#include <vector>

namespace treeskel::modeling::detail {

/// What `unite` did.
struct UnionResult {
  TreeMesh mesh;
  std::size_t united = 0;        ///< pieces now part of the mesh
  TreeMesh apart;                ///< the pieces the union could not take, as they are (not in `mesh`)
  std::size_t failed = 0;        ///< pieces the union could not take (in `apart`)
  std::size_t skipped = 0;       ///< pieces left out of the mesh: the budget of corefinements was spent
  std::size_t batches = 0;       ///< corefinements run (with the base or among the pieces)
  std::size_t welded = 0;        ///< edges shorter than the weld distance, collapsed
  std::size_t voids = 0;         ///< pockets the pieces enclosed, filled (their inward surfaces removed)
};

/// A local coordinate as the 32-bit float a file holds in the frame `offset` leads to (local +
/// offset), as a double: where the union and its checks round the points.
/// The float goes through memory: GCC 12 at -O3 with -frounding-math (which CGAL needs) vectorized a
/// loop of this over x, y and z and dropped the round trip through float for two of the three, so
/// that the union's points, and the points the crossing tests ran on, were not what files hold.
inline double file_float(double local, double offset) {
  volatile float rounded = static_cast<float>(local + offset);
  return static_cast<double>(rounded);
}

/// How deep points lie inside a closed mesh (an AABB tree of its faces in doubles, exact side
/// predicates; built once).
class MeshDepth {
 public:
  explicit MeshDepth(const TreeMesh& mesh);
  ~MeshDepth();
  MeshDepth(const MeshDepth&) = delete;
  MeshDepth& operator=(const MeshDepth&) = delete;
  /// The distance from `p` to the mesh's surface: positive inside, negative outside.
  double operator()(const Eigen::Vector3d& p) const;
  /// The point of the mesh's surface nearest to `p` (`p` itself for a mesh without faces).
  Eigen::Vector3d nearest(const Eigen::Vector3d& p) const;

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
};

/// The box of the points of `mesh`.
Eigen::AlignedBox3d bounding_box(const TreeMesh& mesh);

/// Collapses the edges of `mesh` shorter than `weld` (where the collapse keeps it manifold), those
/// with an end in one of the boxes `where` if it is not empty; returns how many. Corefinement puts vertices where two surfaces cross, some closer together than the
/// 32-bit floats of most mesh formats can tell apart: a reader would merge them into a
/// non-manifold spot.
std::size_t weld_short_edges(TreeMesh& mesh, double weld, const std::vector<Eigen::AlignedBox3d>& where = {});

/// For each face of `faces` (indices), collapses its shortest edge no longer than `max_length`
/// whose collapse keeps the mesh manifold and turns no face over (slivers no taller than `sliver`
/// aside); returns how many. Rounding can leave a sliver of the union crossing its neighbour: its
/// shortest edge is where it folds. With `moved`, appends for each collapse a box that holds every
/// face it changed, before and after.
std::size_t collapse_shortest_edges(TreeMesh& mesh, const std::vector<std::size_t>& faces, double max_length,
                                   double sliver = 0.0, std::vector<Eigen::AlignedBox3d>* moved = nullptr);

/// The faces `faces` (indices) and every face that shares a vertex with one of them, in order of
/// their indices, each once.
std::vector<std::size_t> faces_around(const TreeMesh& mesh, const std::vector<std::size_t>& faces);

/// Where two parts of a union touch at a single point, a vertex holds two fans of faces (each fan
/// the faces around it that share edges), which OpenMesh cannot hold (it would drop faces and leave
/// holes): the fan of the vertex's first face keeps it, and each other fan, in the order of its
/// first face, gets a copy appended to `points`. `faces` index `points`.
void split_pinched_vertices(std::vector<std::array<double, 3>>& points, std::vector<std::array<std::size_t, 3>>& faces);

/// The order a union's vertices are written in, which must not follow corefinement's (that follows
/// memory addresses): by `rounded` (the points as files hold them), then `unrounded` (as doubles),
/// then `exact_less(a, b)` (the exact points: a cut's points can lie closer together than doubles
/// tell apart; Paris_Luxembourg_1 has ten at one double), then, for the same exact point in two
/// parts that touch, by the vertices `neighbours(i)` gives, each list sorted by `exact_less`.
template <class ExactLess, class Neighbours>
std::vector<std::size_t> canonical_vertex_order(const std::vector<std::array<double, 3>>& rounded,
                                                const std::vector<std::array<double, 3>>& unrounded,
                                                const ExactLess& exact_less, const Neighbours& neighbours) {
  const auto sorted_neighbours = [&](std::size_t i) {
    std::vector<std::size_t> out = neighbours(i);
    std::sort(out.begin(), out.end(), exact_less);
    return out;
  };
  std::vector<std::size_t> order(rounded.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (rounded[a] != rounded[b]) return rounded[a] < rounded[b];
    if (unrounded[a] != unrounded[b]) return unrounded[a] < unrounded[b];
    if (exact_less(a, b)) return true;
    if (exact_less(b, a)) return false;
    const auto na = sorted_neighbours(a), nb = sorted_neighbours(b);
    return std::lexicographical_compare(na.begin(), na.end(), nb.begin(), nb.end(), exact_less);
  });
  return order;
}

/// The unions of groups of pieces that `unite` made, kept for its next calls: a group of the same
/// pieces (the same points and faces, in the same order) takes the union made before instead of
/// making it again. A caller that nudges a piece and unites every piece again (`add_pieces`) redid
/// every group; on AdTree's tree7 with `--complete-all`, a fifth of its model. The mesh is the same
/// (a union is the same for the same inputs); `UnionResult::batches` counts only the corefinements
/// run.
class GroupUnions {
 public:
  GroupUnions();
  ~GroupUnions();
  GroupUnions(const GroupUnions&) = delete;
  GroupUnions& operator=(const GroupUnions&) = delete;
  struct Store;
  Store& store() { return *store_; }

 private:
  std::unique_ptr<Store> store_;
};

/// Unites `pieces` with `base`. Each input must be closed, manifold and free of self-intersections.
/// Pieces that cross or hold one another are united among themselves first (at most 8 a group); then
/// all the groups go into one corefinement with `base` (its cost follows the size of `base`, not of
/// the pieces). The pieces left over (a group was full, or refused them, or `base` refused their
/// group) follow in layers of pieces whose boxes do not overlap, a corefinement a layer; a layer
/// the union refuses goes one piece at a time, and a piece refused alone is kept beside the mesh as
/// a component of its own (counted in `failed`), never left out.
/// Voids the union encloses between the pieces and `base` are filled (see `UnionResult::voids`).
/// The result's points are rounded to 32-bit floats in the frame `offset` leads to (local + offset),
/// and its edges shorter than `weld` collapsed (see `weld_short_edges`; within `where` if given).
/// `pieces_tested`: the caller has tested every piece for self-intersections already (the sweep
/// does), so they are not tested again (closedness still is). `made`: the groups' unions of earlier
/// calls, taken again for the same pieces and added to (see `GroupUnions`).
UnionResult unite(const TreeMesh& base, const std::vector<TreeMesh>& pieces, double weld,
                  const Eigen::Vector3d& offset = Eigen::Vector3d::Zero(),
                  const std::vector<Eigen::AlignedBox3d>& where = {}, bool pieces_tested = false,
                  GroupUnions* made = nullptr);

}  // namespace treeskel::modeling::detail
