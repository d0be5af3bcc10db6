#include "pieces.h"

#include "mesh_union.h"
#include "skeleton_parts.h"
#include "treeskel/error.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <optional>
#include <tuple>
#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace treeskel::modeling::detail {

namespace {

/// Rounds of collapsing the slivers of a union that cross a neighbour once rounded to floats:
/// kFlatRounds, then on while they make progress (a round that leaves fewer crossings than the best
/// before it; none for kSliverStall rounds ends them), at most kSliverRounds. Collapses can make new
/// slivers, and the count then wanders: where the rounds past kFlatRounds do not clear every
/// crossing, the union is tried again from where kFlatRounds left it, as before there were more.
/// (Four rounds left 30 of 243 crossings of AdTree's Lille_11 in the frame of a PLY, whose floats
/// step by 6e-5 m there, and its union was tried again: 3.4 s for the model instead of 2.2 s.) Then
/// the longest edge (in weld distances) such a collapse may remove.
constexpr int kFlatRounds = 4;
constexpr int kSliverRounds = 12;
constexpr int kSliverStall = 2;
constexpr double kSliverEdges = 1000.0;
/// Faces no taller than this (in weld distances) have no direction a collapse must keep.
constexpr double kSliverHeight = 10.0;
/// Most pieces swept, and most unions tried (retries included), for one tree: a leafy crown whose
/// twigs cross one another everywhere can leave thousands of pieces, each failing its union; past
/// these, what is left is left out and counted in `pieces_failed` (the summary warns) rather than
/// taking minutes and gigabytes.
constexpr std::size_t kMaxPieces = 2000;
constexpr std::size_t kMaxUnions = 200;
/// How far (in the tree's extent) a piece whose union crossed itself once rounded to floats is moved
/// before it is tried again, and how many times at most (each in another direction). Two surfaces
/// that nearly touch where the union cuts them leave slivers that floats fold; moved by a fifth of a
/// millimetre on a 20 m tree, far below what a scan resolves, they no longer nearly touch there.
constexpr double kNudge = 1e-5;
constexpr int kMaxNudges = 2;

using Box = Eigen::AlignedBox3d;
using Pairs = std::vector<std::pair<std::size_t, std::size_t>>;

/// A piece: its skeleton (to split it if it cannot be united whole) and its mesh.
struct Piece {
  Skeleton skeleton;
  TreeMesh mesh;
  int nudges = 0;  // times moved to clear a crossing (see Uniter::nudge)
  SweepStats counts;  // what its sweep added to the tree's counts (taken back when it is split)
};

Box face_box(const TreeMesh& mesh, TreeMesh::FaceHandle f) {
  Box b;
  auto h = mesh.halfedge_handle(f);
  for (int corner = 0; corner < 3; ++corner, h = mesh.next_halfedge_handle(h)) {  // a TriMesh: triangles
    const auto& p = mesh.point(mesh.to_vertex_handle(h));
    b.extend(Eigen::Vector3d(p[0], p[1], p[2]));
  }
  return b;
}

using Key = std::array<double, 3>;
struct KeyHash {
  std::size_t operator()(const Key& k) const {
    std::size_t h = 0;
    for (double x : k) h = h * 1000003u ^ std::hash<double>()(x);
    return h;
  }
};

/// A point as the 32-bit floats of the frame `offset` leads to hold it.
Key world_key(const TreeMesh::Point& p, const Eigen::Vector3d& offset) {
  Key k;
  for (int a = 0; a < 3; ++a) k[static_cast<std::size_t>(a)] = file_float(p[a], offset[a]);
  return k;
}

/// Boxes (grown by `slack`) of the faces of `united` with a point that is in none of `inputs` (once
/// rounded to the floats of the frame): the faces the union made where the surfaces cross.
std::vector<Box> changed_boxes(const TreeMesh& united, const std::vector<const TreeMesh*>& inputs,
                               const Eigen::Vector3d& offset, double slack) {
  std::size_t count = 0;
  for (const TreeMesh* m : inputs) count += m->n_vertices();
  std::unordered_set<Key, KeyHash> old(count);
  for (const TreeMesh* m : inputs)
    for (auto v : m->vertices()) old.insert(world_key(m->point(v), offset));
  std::vector<char> fresh(united.n_vertices());  // a point none of the inputs has: once per vertex
  for (auto v : united.vertices()) fresh[static_cast<std::size_t>(v.idx())] = !old.count(world_key(united.point(v), offset));
  std::vector<Box> out;
  for (auto f : united.faces()) {
    const auto corners = united.fv_range(f);
    if (std::none_of(corners.begin(), corners.end(), [&](auto v) { return fresh[static_cast<std::size_t>(v.idx())] != 0; }))
      continue;
    Box b = face_box(united, f);
    b.min().array() -= slack;
    b.max().array() += slack;
    out.push_back(b);
  }
  return out;
}

/// Boxes hashed into uniform grids, to tell quickly whether a box meets one of them. (CGAL's box
/// intersection took a tenth of a second for the changed faces of a union against a 100k-face tree,
/// as long as the union.) The grids form a ladder: the finest has cells as long as the median box's
/// longest side, each next one cells kCellGrowth times longer, and each box goes to the finest grid
/// on which it covers at most kMaxCells cells. A query is first clipped to the bounds of each grid's
/// boxes, so a face far from every box costs a few comparisons. (With one grid and the larger boxes
/// in a list tested one by one, a pine of the LPine1 plot made 600 million box tests, 8% of its model.)
class BoxGrid {
 public:
  explicit BoxGrid(const std::vector<Box>& boxes) : boxes_(boxes) {
    if (boxes.empty()) return;
    std::vector<double> sides;
    for (const auto& b : boxes) sides.push_back(b.sizes().maxCoeff());
    std::nth_element(sides.begin(), sides.begin() + static_cast<std::ptrdiff_t>(sides.size() / 2), sides.end());
    const double cell = std::max(sides[sides.size() / 2], 1e-12);
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      bound_.extend(boxes[i]);
      std::size_t level = 0;
      while (level + 1 < kLevels && cell_count(boxes[i], cell_of(level, cell)) > kMaxCells) ++level;
      while (levels_.size() <= level) levels_.push_back({cell_of(levels_.size(), cell), {}, {}, {}, {}});
      Level& l = levels_[level];
      l.bound.extend(boxes[i]);
      l.members.push_back(i);
      if (cell_count(boxes[i], l.cell) > kMaxCells) {  // larger than the coarsest grid holds
        l.loose.push_back(i);
        continue;
      }
      const auto [lo, hi] = cells(boxes[i], l.cell);
      for (auto x = lo[0]; x <= hi[0]; ++x)
        for (auto y = lo[1]; y <= hi[1]; ++y)
          for (auto z = lo[2]; z <= hi[2]; ++z) l.grid[{x, y, z}].push_back(i);
    }
  }

  bool meets(const Box& b) const {
    if (boxes_.empty() || !bound_.intersects(b)) return false;
    for (const Level& l : levels_) {
      if (l.members.empty() || !l.bound.intersects(b)) continue;
      for (std::size_t i : l.loose)
        if (boxes_[i].intersects(b)) return true;
      // Every box of this grid lies in its bound: what meets `b` meets the part of `b` inside it.
      const Box q = b.intersection(l.bound);
      if (cell_count(q, l.cell) > kMaxCells) {  // a large query: this grid's boxes, one by one
        if (std::any_of(l.members.begin(), l.members.end(), [&](std::size_t i) { return boxes_[i].intersects(b); }))
          return true;
        continue;
      }
      const auto [lo, hi] = cells(q, l.cell);
      for (auto x = lo[0]; x <= hi[0]; ++x)
        for (auto y = lo[1]; y <= hi[1]; ++y)
          for (auto z = lo[2]; z <= hi[2]; ++z) {
            const auto it = l.grid.find({x, y, z});
            if (it == l.grid.end()) continue;
            for (std::size_t i : it->second)
              if (boxes_[i].intersects(b)) return true;
          }
    }
    return false;
  }

 private:
  static constexpr double kMaxCells = 64;
  static constexpr double kCellGrowth = 4;
  static constexpr std::size_t kLevels = 16;
  using Cell = std::array<std::int64_t, 3>;
  struct CellHash {
    std::size_t operator()(const Cell& c) const {  // unsigned: wraps, where signed would overflow
      const auto u = [](std::int64_t x) { return static_cast<std::uint64_t>(x); };
      return static_cast<std::size_t>(u(c[0]) * 73856093u ^ u(c[1]) * 19349663u ^ u(c[2]) * 83492791u);
    }
  };
  struct Level {
    double cell;
    Box bound;                                                      // of the boxes on this grid
    std::vector<std::size_t> members;                               // those boxes
    std::vector<std::size_t> loose;                                 // of them, too large to hash
    std::unordered_map<Cell, std::vector<std::size_t>, CellHash> grid;  // cell -> boxes over it
  };
  static double cell_of(std::size_t level, double finest) { return finest * std::pow(kCellGrowth, static_cast<double>(level)); }
  /// The cells a box covers, from its lowest to its highest (clamped far inside what int64 holds).
  static std::pair<Eigen::Array<std::int64_t, 3, 1>, Eigen::Array<std::int64_t, 3, 1>> cells(const Box& b, double cell) {
    constexpr double kFar = 1e15;
    auto at = [&](const Eigen::Vector3d& p) { return (p.array() / cell).floor().max(-kFar).min(kFar).cast<std::int64_t>().eval(); };
    return {at(b.min()), at(b.max())};
  }
  static double cell_count(const Box& b, double cell) {
    const auto [lo, hi] = cells(b, cell);
    return (hi - lo + 1).cast<double>().prod();
  }
  const std::vector<Box>& boxes_;
  Box bound_;  // of all the boxes
  std::vector<Level> levels_;
};

/// Crossings (faces of `mesh`, by index) among the faces that meet `regions`, in the floats of the
/// frame `offset` leads to. A crossing the union added pairs a face it made with one whose box
/// meets that face's: testing the faces that meet the changed faces' boxes, before and after,
/// tells whether it added one.
Pairs crossings_in(const TreeMesh& mesh, const Eigen::Vector3d& offset, const std::vector<Box>& regions) {
  const std::vector<std::size_t> faces = faces_touching(mesh, regions);
  return self_intersecting_faces_at(mesh, world_floats(mesh, offset), &faces);
}

/// Sweeps pieces and unites them with a mesh (see add_pieces).
class Uniter {
 public:
  /// `clean_base`: the mesh the pieces go into holds no crossing in the floats of the frame (the
  /// sweep's whole-mesh test found none), so neither does any union `unite` returns (each adds no
  /// crossing), and a union's regions need not be tested on its base.
  Uniter(const SweepOptions& options, double extent, const Eigen::Vector3d& frame, const TreeScale& scale, SweepStats& st,
         bool clean_base)
      : o_(options), extent_(extent), frame_(frame), scale_(scale), st_(st), clean_base_(clean_base) {}

  /// Sweeps `first` on its own into `out`, and each piece its sweep leaves apart; a piece that does
  /// not sweep is split until its parts do. (A loop, not a recursion: a crowded crown can leave
  /// pieces apart from pieces thousands deep.)
  void sweep(const Skeleton& first, std::vector<Piece>& out) {
    std::vector<Skeleton> todo{first};
    while (!todo.empty()) {
      const Skeleton piece = std::move(todo.back());
      todo.pop_back();
      if (++swept_ > kMaxPieces) {
        ++st_.pieces_failed;
        continue;
      }
      SweepStats piece_stats;
      std::vector<Skeleton> apart;
      Skeleton kept;
      try {
        TreeMesh mesh = sweep_part(piece, o_, frame_, scale_, piece_stats, apart, &kept, BaseCap::hidden);
        if (o_.repair && piece_stats.self_intersections > 0) throw Error("the piece crosses itself");
        // A sweep that kept no segment, or left apart a piece as large as this one, made no
        // progress (the loop would sweep the same piece again and again): split it instead.
        if (kept.node_count() < 2 ||
            std::any_of(apart.begin(), apart.end(), [&](const Skeleton& a) { return a.node_count() >= piece.node_count(); }))
          throw Error("the piece's sweep left it apart whole");
        add_counts(st_, piece_stats);
        out.push_back({std::move(kept), std::move(mesh), 0, piece_stats});
        ++st_.pieces;
        for (auto& a : apart) todo.push_back(std::move(a));
        continue;
      } catch (const Error&) {
      }
      auto parts = split_piece(piece);
      if (parts.empty()) ++st_.pieces_failed;  // a single segment that cannot be swept: said in the report
      for (auto& part : parts) todo.push_back(std::move(part));
    }
  }

  /// Sweeps every one of `pieces` as `sweep` does, side by side on the cores: each into a list and
  /// counts of its own, joined in their order, which is what sweeping one after the other gives
  /// (tested: MeshUnion.OneThreadOrTwoGiveTheSameMesh). Past kMaxPieces sweeps in all, where the
  /// order decides which pieces are left out, they are swept one after the other instead.
  std::vector<Piece> sweep_all(const std::vector<Skeleton>& pieces) {
    struct Own {
      std::vector<Piece> out;
      SweepStats st;
      std::size_t swept = 0;
    };
    std::vector<Own> own(pieces.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pieces.size(), 1), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i) {
        Uniter alone(o_, extent_, frame_, scale_, own[i].st, clean_base_);
        alone.sweep(pieces[i], own[i].out);
        own[i].swept = alone.swept_;
      }
    });
    std::size_t swept = swept_;
    for (const auto& p : own) swept += p.swept;
    std::vector<Piece> out;
    if (swept > kMaxPieces) {
      for (const auto& piece : pieces) sweep(piece, out);
      return out;
    }
    swept_ = swept;
    for (auto& p : own) {
      add_counts(st_, p.st);
      std::move(p.out.begin(), p.out.end(), std::back_inserter(out));
    }
    return out;
  }

  /// The pieces the unions refused, to be set beside the mesh once no union is left to run.
  const std::vector<TreeMesh>& apart() const { return apart_; }

  /// `base` with `pieces` united into it, adding no crossing in the floats of the frame.
  TreeMesh unite(const TreeMesh& base, std::vector<Piece> pieces) {
    if (pieces.empty()) return base;
    if (++unions_ > kMaxUnions) {
      st_.pieces_failed += pieces.size();
      st_.pieces -= std::min(st_.pieces, pieces.size());
      return base;
    }
    // Boxes grown by the longest edge a sliver collapse may remove.
    const double slack = kSliverEdges * o_.weld * extent_;
    std::vector<TreeMesh> meshes;
    std::vector<Box> boxes;
    for (auto& p : pieces) {
      Box b = bounding_box(p.mesh);
      b.min().array() -= slack;
      b.max().array() += slack;
      boxes.push_back(b);
      meshes.push_back(p.mesh);
    }
    // With the repair on, every piece's sweep was tested for self-intersections (see `sweep`).
    UnionResult united = detail::unite(base, meshes, o_.weld * extent_, frame_, boxes, o_.repair, &made_);
    TreeMesh mesh = std::move(united.mesh);
    std::size_t welded = united.welded;
    st_.unions += united.batches;
    if (o_.repair) {
      std::vector<const TreeMesh*> inputs{&base};
      for (const auto& p : pieces) inputs.push_back(&p.mesh);
      const std::vector<Box> regions = changed_boxes(mesh, inputs, frame_, slack);
      const std::size_t before = clean_base_ ? 0 : crossings_in(base, frame_, regions).size();
      Pairs pairs = crossings_in(mesh, frame_, regions);
      std::size_t best = pairs.size();
      std::optional<std::pair<TreeMesh, Pairs>> after_flat;  // where the flat rounds left it
      for (int round = 0, stalled = 0;
           round < kSliverRounds && (round < kFlatRounds || stalled < kSliverStall) && pairs.size() > before; ++round) {
        if (round == kFlatRounds) after_flat.emplace(mesh, pairs);
        std::vector<std::size_t> faces;
        for (const auto& [a, b] : pairs) faces.insert(faces.end(), {a, b});
        // After a round without progress, the faces around the crossing ones go too (AdTree's Lille_2
        // as PLY stalled at two crossings of faces a few millimetres across, and its union was made
        // again: 46 corefinements instead of 23).
        if (stalled > 0) {
          faces = faces_around(mesh, faces);  // in order, each once
        } else {
          std::sort(faces.begin(), faces.end());
          faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
        }
        // Once rounded, only a face a collapse changed, or one that crossed before, can cross: the
        // next test is of the faces near those (their boxes grown by the slack), not of the whole
        // region the union changed (each round's test cost 0.08-0.1 s on AdTree's Lille_2 and
        // Paris_Luxembourg_1, and both took two rounds).
        std::vector<Box> near;
        for (std::size_t f : faces) near.push_back(face_box(mesh, mesh.face_handle(static_cast<unsigned>(f))));
        const std::size_t collapsed = collapse_shortest_edges(mesh, faces, slack, kSliverHeight * o_.weld * extent_, &near);
        if (collapsed == 0) break;
        welded += collapsed;
        for (Box& b : near) {
          b.min().array() -= slack;
          b.max().array() += slack;
        }
        pairs = crossings_in(mesh, frame_, near);
        stalled = pairs.size() < best ? 0 : stalled + 1;
        best = std::min(best, pairs.size());
      }
      if (pairs.size() > before) {
        if (after_flat) std::tie(mesh, pairs) = std::move(*after_flat);
        return retry(base, std::move(pieces), mesh, pairs, boxes);
      }
    }
    if (united.apart.n_faces() > 0) apart_.push_back(std::move(united.apart));
    st_.welded_edges += welded;
    st_.voids_filled += united.voids;
    st_.pieces_failed += united.skipped;
    st_.pieces -= std::min(st_.pieces, united.skipped);
    st_.pieces_apart += united.failed;
    return mesh;
  }

 private:
  /// The union of `pieces` with `base` added the crossings `pairs` (faces of `united`): the pieces
  /// near them are united on their own, before the others, and a single piece is split (`narrow`).
  TreeMesh retry(const TreeMesh& base, std::vector<Piece> pieces, const TreeMesh& united, const Pairs& pairs,
                 const std::vector<Box>& boxes) {
    std::vector<Box> spots;  // the boxes of the faces that cross
    for (const auto& [a, b] : pairs)
      for (std::size_t f : {a, b}) spots.push_back(face_box(united, united.face_handle(static_cast<unsigned>(f))));
    if (nudge(pieces, spots)) return unite(base, std::move(pieces));
    if (pieces.size() == 1) return narrow(base, std::move(pieces.front()), spots);
    std::vector<bool> suspect(pieces.size(), false);
    for (const Box& fb : spots)
      for (std::size_t i = 0; i < boxes.size(); ++i) suspect[i] = suspect[i] || boxes[i].intersects(fb);
    std::vector<Piece> clear, near;
    for (std::size_t i = 0; i < pieces.size(); ++i) (suspect[i] ? near : clear).push_back(std::move(pieces[i]));
    // What may fail again goes first, while the mesh is smaller: each try of it is a corefinement
    // with the whole mesh. (Last, after a limb of 226k faces, each try of a crossing twig cost a
    // second instead of a fifth in a pine of the LPine1 plot.)
    if (clear.empty() || near.empty()) {  // no telling which: in halves, the smaller pieces first
      std::vector<Piece>& all = clear.empty() ? near : clear;
      std::stable_sort(all.begin(), all.end(), [](const Piece& a, const Piece& b) { return a.mesh.n_faces() < b.mesh.n_faces(); });
      std::vector<Piece> second(std::make_move_iterator(all.begin() + static_cast<std::ptrdiff_t>(all.size() / 2)),
                                std::make_move_iterator(all.end()));
      all.resize(all.size() / 2);
      return unite(unite(base, std::move(all)), std::move(second));
    }
    return unite(unite(base, std::move(near)), std::move(clear));
  }

  /// Moves every one of `pieces` with faces at `spots` by `kNudge` of the extent, the pieces there
  /// taking six directions in turn (two each: one per move), so that two of them that cross each other
  /// there move apart as well as each from the rest; false if none there could move (each moves at most
  /// `kMaxNudges` times, and not where it would cross itself). Moving only the smallest one there took
  /// as many unions of the whole tree as there were pieces to try: four on AdTree's
  /// Paris_Luxembourg_1, whose crossing spots touched two pieces. (In a pine of the LPine1 plot one
  /// move cleared what splitting took 28 corefinements of the whole tree to leave a 1 cm stub out of.)
  bool nudge(std::vector<Piece>& pieces, const std::vector<Box>& spots) {
    // Unit directions far from each other and from the axes (along which the pieces' rings lie).
    static constexpr double kWays[][3] = {{0.5345, 0.2673, 0.8018},  {-0.7071, 0.5774, -0.4082}, {0.2673, -0.8018, 0.5345},
                                          {-0.4082, -0.7071, 0.5774}, {0.8018, 0.5345, -0.2673},  {-0.5774, 0.4082, 0.7071}};
    constexpr std::size_t kWayCount = sizeof(kWays) / sizeof(kWays[0]);
    const double step = kNudge * extent_;
    bool any = false;
    std::size_t k = 0;  // the pieces at the spots so far
    for (auto& p : pieces) {
      if (faces_touching(p.mesh, spots).empty()) continue;
      const std::size_t way = (k++ * kMaxNudges + static_cast<std::size_t>(p.nudges)) % kWayCount;
      if (p.nudges >= kMaxNudges) continue;
      TreeMesh moved = p.mesh;
      for (auto v : moved.vertices()) {
        auto q = moved.point(v);
        for (int a = 0; a < 3; ++a) q[a] += step * kWays[way][a];
        moved.set_point(v, q);
      }
      if (!self_intersecting_faces_at(moved, world_floats(moved, frame_)).empty()) continue;
      p.mesh = std::move(moved);
      ++p.nudges;
      ++st_.pieces_nudged;
      any = true;
    }
    return any;
  }

  /// `base` with `piece`, whose union with it crossed itself at `spots`, split until the part at
  /// the spots is alone: while exactly one of a split's parts meets them, the others are set aside
  /// and that one is split again, without a union. Then the parts at the spots go in one union
  /// (retried as any, if it fails) and the parts set aside in the next. (Uniting each split to find
  /// out, as before, cost three corefinements of the whole tree a split: in a pine of the LPine1
  /// plot, a crossing at the root of a 212-node limb took six splits and 20 of its 32 s.)
  TreeMesh narrow(const TreeMesh& base, Piece piece, const std::vector<Box>& spots) {
    if (st_.pieces > 0) --st_.pieces;
    std::vector<Piece> aside;
    for (;;) {
      const auto parts = split_piece(piece.skeleton);
      if (parts.empty()) {
        if (aside.empty()) {  // a single segment, refused alone: left out (said in the report)
          ++st_.pieces_failed;
          return base;
        }
        ++st_.pieces;  // tried below, counted as the pieces `sweep` gives
        break;
      }
      take_counts(st_, piece.counts);  // its parts' sweeps count their branches and joins again
      std::vector<Piece> smaller;
      for (const auto& part : parts) sweep(part, smaller);
      std::vector<Piece> at;  // the parts at the spots
      for (auto& p : smaller) {
        const Box b = bounding_box(p.mesh);
        (std::any_of(spots.begin(), spots.end(), [&](const Box& s) { return s.intersects(b); }) ? at : aside).push_back(std::move(p));
      }
      if (at.size() != 1) return unite(unite(base, std::move(at)), std::move(aside));  // none, or several: no one to split
      piece = std::move(at.front());
      if (st_.pieces > 0) --st_.pieces;  // split again, not united
    }
    std::vector<Piece> last{std::move(piece)};
    return unite(unite(base, std::move(last)), std::move(aside));
  }

  const SweepOptions& o_;
  double extent_;
  Eigen::Vector3d frame_;
  TreeScale scale_;
  SweepStats& st_;
  bool clean_base_;
  std::size_t swept_ = 0, unions_ = 0;
  std::vector<TreeMesh> apart_;  // the pieces the unions refused
  GroupUnions made_;             // the groups' unions made so far, for a union made again after a nudge
};

/// Adds the vertices and faces of `part` to `mesh` as they are.
void append_mesh(TreeMesh& mesh, const TreeMesh& part) {
  std::vector<TreeMesh::VertexHandle> map;
  map.reserve(part.n_vertices());
  for (auto v : part.vertices()) map.push_back(mesh.add_vertex(part.point(v)));
  for (auto f : part.faces()) {
    std::vector<TreeMesh::VertexHandle> corners;
    for (auto v : part.fv_range(f)) corners.push_back(map[static_cast<std::size_t>(v.idx())]);
    mesh.add_face(corners);
  }
}

/// Applies `op(count of to, count of from)` to every count of what a piece's sweep put into the
/// mesh: its branches, joins and what was thinned, left out or swept apart.
template <class Op>
void each_content_count(SweepStats& to, const SweepStats& from, Op op) {
  op(to.branches, from.branches);
  op(to.junctions, from.junctions);
  op(to.merged_forks, from.merged_forks);
  op(to.straightened_branches, from.straightened_branches);
  op(to.thin_left_out, from.thin_left_out);
  op(to.relocated_branches, from.relocated_branches);
  op(to.twigs_absorbed, from.twigs_absorbed);
  op(to.joins_thinned, from.joins_thinned);
  op(to.joins_dropped, from.joins_dropped);
  op(to.repaired_shrunk, from.repaired_shrunk);
  op(to.repaired_dropped, from.repaired_dropped);
}

}  // namespace

void add_counts(SweepStats& to, const SweepStats& from) {
  each_content_count(to, from, [](auto& a, auto b) { a += b; });
  // The work done, which stays done when a piece is split.
  to.repair_rounds += from.repair_rounds;
  to.late_repair_rounds += from.late_repair_rounds;
  to.attempts += from.attempts;
  to.pieces += from.pieces;
  to.pieces_apart += from.pieces_apart;
  to.pieces_nudged += from.pieces_nudged;
  to.pieces_failed += from.pieces_failed;
  to.unions += from.unions;
  to.welded_edges += from.welded_edges;
  to.voids_filled += from.voids_filled;
}

void take_counts(SweepStats& to, const SweepStats& from) {
  each_content_count(to, from, [](auto& a, auto b) { a -= std::min(a, b); });
}

std::vector<TreeMesh::Point> world_floats(const TreeMesh& mesh, const Eigen::Vector3d& offset) {
  std::vector<TreeMesh::Point> out;
  out.reserve(mesh.n_vertices());
  for (auto v : mesh.vertices()) {
    const Key w = world_key(mesh.point(v), offset);
    out.emplace_back(w[0], w[1], w[2]);
  }
  return out;
}

std::vector<std::size_t> faces_touching(const TreeMesh& mesh, const std::vector<Box>& boxes) {
  const BoxGrid grid(boxes);
  // Each face on its own (the grid is only read), gathered in face order: the same list for any
  // number of threads. (One after the other, 50-80 ms a call on a tree of 300k faces.)
  const std::size_t n = mesh.n_faces();
  std::vector<char> touches(n, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t f = range.begin(); f < range.end(); ++f) {
      const auto face = mesh.face_handle(static_cast<unsigned>(f));
      if (mesh.has_face_status() && mesh.status(face).deleted()) continue;  // as faces() skips them
      touches[f] = grid.meets(face_box(mesh, face)) ? 1 : 0;
    }
  });
  std::vector<std::size_t> out;
  for (std::size_t f = 0; f < n; ++f)
    if (touches[f]) out.push_back(f);
  return out;
}

std::vector<Skeleton> split_piece(const Skeleton& piece) {
  const ChainTree t = build_chains(piece);
  std::vector<Skeleton> parts;
  if (t.children[piece.root].size() > 1) {
    for (const auto& c : t.chains)
      if (c.nodes.front() == piece.root) parts.push_back(piece_of(piece, t, c.nodes[1]));
    return parts;
  }
  const auto& base = t.chains.front();
  for (std::size_t c : base.children) parts.push_back(piece_of(piece, t, t.chains[c].nodes[1]));
  if (base.nodes.size() < 3) {
    // A single segment: alone, if it carries branches (else it cannot be split).
    if (!parts.empty()) parts.push_back(path_of(piece, base.nodes));
    return parts;
  }
  const std::size_t m = base.nodes.size() / 2;
  if (m == 1 && !parts.empty()) {
    // A base of two segments under a fork stays whole, its arms apart: halved, its halves share only
    // the middle node, not a segment, and the half from there on, which the arms' stubs go into, met
    // nothing (a limb of AdTree's Lille_11 with --complete-all, written beside the tree).
    parts.push_back(path_of(piece, base.nodes));
    return parts;
  }
  parts.push_back(path_of(piece, {base.nodes.begin(), base.nodes.begin() + static_cast<std::ptrdiff_t>(m) + 1}));
  parts.push_back(path_of(piece, {base.nodes.begin() + static_cast<std::ptrdiff_t>(m > 1 ? m - 1 : m), base.nodes.end()}));
  return parts;
}

TreeMesh add_pieces(TreeMesh mesh, const std::vector<Skeleton>& pieces, const SweepOptions& options,
                    const Eigen::Vector3d& frame, const TreeScale& scale, SweepStats& st) {
  // The sweep's whole-mesh test ran and found no crossing (the pieces' sweeps do not count there).
  const bool clean = options.repair && st.self_intersections == 0;
  Uniter uniter(options, bounding_box(mesh).sizes().maxCoeff(), frame, scale, st, clean);
  auto start = std::chrono::steady_clock::now();
  std::vector<Piece> swept = uniter.sweep_all(pieces);
  st.pieces_seconds = seconds_since(start);
  start = std::chrono::steady_clock::now();
  TreeMesh united = uniter.unite(mesh, std::move(swept));
  st.union_seconds = seconds_since(start);
  for (const auto& part : uniter.apart()) append_mesh(united, part);
  return united;
}

}  // namespace treeskel::modeling::detail
