#include "treeskel/modeling/sweep.h"

#include "treeskel/disjoint_sets.h"
#include "treeskel/error.h"
#include "treeskel/geometry.h"
#include "treeskel/modeling/chains.h"
#include "attempt.h"
#include "joins.h"
#include "tessellate.h"
#include "mesh_union.h"
#include "pieces.h"
#include "repair.h"
#include "skeleton_parts.h"
#include "tube.h"

#include <Eigen/Geometry>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <set>

namespace treeskel::modeling {

namespace {

/// Per node, the frustum between it and its parent (radii raised to `floor`); 0 at the root.
std::vector<double> edge_wood(const Skeleton& skeleton, const ChainTree& tree, double floor) {
  std::vector<double> wood(skeleton.node_count(), 0.0);
  for (NodeId v = 0; v < skeleton.node_count(); ++v) {
    const NodeId p = tree.parent[v];
    if (p == v) continue;
    wood[v] = frustum_volume(std::max(skeleton[v].radius, floor), std::max(skeleton[p].radius, floor),
                             (skeleton[v].position - skeleton[p].position).norm());
  }
  return wood;
}

/// The wood of the whole skeleton: its frustums, radii raised to `floor`.
double wood_volume(const Skeleton& skeleton, double floor) {
  const auto wood = edge_wood(skeleton, build_chains(skeleton), floor);
  return std::accumulate(wood.begin(), wood.end(), 0.0);
}

using Eigen::Vector3d;
using detail::compatible;
using detail::path_of;
using detail::piece_of;
using detail::relocate_narrow_branches;
using detail::subtree;
using detail::make_polyline;
using detail::Polyline;
using detail::reach_beyond;
using detail::Ring;
using detail::ring_at;
using detail::lay_rings;
using detail::tip_arc;
using detail::area_factor;
using detail::Attempt;
using detail::assemble;
using detail::clearing_factor;
using detail::crossing_parts;
using detail::forks_up_to;
using detail::Arm;
using detail::Cluster;
using detail::Join;
using detail::kRingClearanceRadii;
using detail::place_rings;
using detail::tessellate;
using detail::Tube;
/// How much of its branch's length a join's ring may take: a twig's (the rest is its tip's cone),
/// the base chain's, and a chain's between two joins (less what the other join took).
constexpr double kTwigRoom = 0.7;
constexpr double kBaseRoom = 0.8;
constexpr double kInnerRoom = 0.9;
/// Where two arms' rings cannot clear each other at a narrow fork, both thin by this factor where
/// they meet (their necks), up to `SweepOptions::max_necks` times.
constexpr double kNeckFactor = 0.8;
/// A chain whose end rings leave less than this share of its length between them has no room.
constexpr double kLeastRoomShare = 0.05;
/// A tip's cone, and the cone closing a join left with one arm, reach at least this many radii
/// past their ring.
constexpr double kConeRadii = 0.25;
/// The rings of the cap that closes the base, from the widest arm's radius down to a point: the
/// first that lies behind every ring of the base's join is taken.
constexpr std::array<double, 5> kBaseCapShares{1.0, 0.75, 0.5, 0.25, 0.0};
/// A chain longer than this many radii between its end rings has room for its tube whatever way it
/// turns (the rings laid along it are checked one against the next).
constexpr double kRoomyChain = 4.0;
/// A band runs between two rings for at most this share of the tree's extent. Where pieces swept
/// apart are united with the tree, the union cuts slivers along the line where two surfaces cross,
/// as long as the faces they cross; at a narrow crossing, rounding the points of a long one to
/// floats folds it into its neighbour, which no short edge's collapse clears (two straight limbs
/// crossing, each a single band: a fold 0.5 m long).
constexpr double kLongestBandShare = 0.02;
/// A piece's base cap (BaseCap::hidden): its apex this many radii into the tube from its first ring,
/// and this many aside, toward where the branch goes turned by kHiddenBaseTurn (radians) about the axis.
constexpr double kHiddenBaseDepth = 0.25;
constexpr double kHiddenBaseAside = 0.25;
constexpr double kHiddenBaseTurn = 0.5;

using UnionFind = DisjointSets<std::size_t>;

class Builder {
 public:
  using HullCache = detail::HullCache;  // the joins' hulls already computed (see tessellate.h)

  /// `fused`: pairs of forks (ids of `sk`) to make one join from the start (see sweep_attached).
  /// `longest_band`: the longest a band of a tube may run between two rings (0: no limit).
  /// `base`: how the root's branch is closed where no join holds the root.
  Builder(const Skeleton& sk, const SweepOptions& o, HullCache& hulls, double longest_band,
          std::vector<std::pair<NodeId, NodeId>> fused = {}, detail::BaseCap base = detail::BaseCap::flat)
      : sk_(sk), o_(o), t_(build_chains(sk)), hulls_(&hulls), fused_(std::move(fused)), base_(base) {
    rule_.spacing = o.ring_spacing;
    rule_.max_turn = o.max_turn;
    rule_.longest_band = longest_band;
  }

  Attempt run() {
    const auto& g = sk_.graph;
    const std::size_t n = boost::num_vertices(g);
    double extent = 0.0;
    for (NodeId v = 0; v < n; ++v) {
      max_radius_ = std::max(max_radius_, g[v].radius);
      extent = std::max(extent, g[v].position.cwiseAbs().maxCoeff());
    }
    eps_ = 1e-9 * std::max({max_radius_, extent, 1e-300});
    rule_.eps = eps_;
    // Polylines; a chain leaving a fork starts with the radius of its own first node.
    const bool root_fork = t_.children[sk_.root].size() >= 2;
    for (const auto& c : t_.chains) {
      std::vector<Vector3d> pts;
      std::vector<double> radii;
      for (NodeId v : c.nodes) {
        pts.push_back(g[v].position);
        radii.push_back(g[v].radius);
      }
      if (c.nodes.front() != sk_.root || root_fork) radii[0] = radii[1];
      lines_.push_back(make_polyline(pts, radii, eps_));
      const double r0 = radii[0];
      sides_.push_back(std::clamp(static_cast<int>(std::lround(o_.trunk_segments * r0 / max_radius_)), o_.min_segments,
                                  o_.max_segments));
    }
    // Junction nodes: forks, and the root when it has several children.
    is_junction_.assign(n, false);
    for (const auto& c : t_.chains)
      if (!c.children.empty()) is_junction_[c.nodes.back()] = true;
    if (root_fork) is_junction_[sk_.root] = true;

    Attempt attempt;
    UnionFind uf(n);
    for (const auto& [a, b] : fused_)
      if (is_junction_[a] && is_junction_[b] && uf.unite(a, b)) ++attempt.merged_forks;
    absorbed_.assign(t_.chains.size(), false);
    // A chain of no length (its nodes at one place: a fork grafted onto another, or a twig that
    // never left its fork) has no ring to place: its forks are one join, and a twig is the join's.
    for (std::size_t c = 0; c < t_.chains.size(); ++c) {
      if (lines_[c].p.size() >= 2) continue;
      const NodeId a = t_.chains[c].nodes.front(), b = t_.chains[c].nodes.back();
      if (!is_junction_[b]) {
        absorbed_[c] = true;
        ++attempt.absorbed;
        continue;
      }
      is_junction_[a] = true;  // the root, when it is where its only branch forks
      if (uf.unite(a, b)) ++attempt.merged_forks;
    }
    thinned_.assign(t_.chains.size(), 0);
    straightened_.assign(t_.chains.size(), false);
    ring_d_.assign(t_.chains.size(), {0.0, 0.0});
    ring_neck_.assign(t_.chains.size(), {1.0, 1.0});
    std::set<std::size_t> settled;  // joins (by representative) whose rings fit as they are
    // Merges change representatives: finds the settled joins again, less those holding a dirty fork.
    auto refresh = [&uf](std::set<std::size_t>& joins, const std::vector<std::size_t>& dirty) {
      std::set<std::size_t> still;
      for (std::size_t id : joins) still.insert(uf.find(id));
      for (std::size_t v : dirty) still.erase(uf.find(v));
      joins = std::move(still);
    };
    for (int round = 0;; ++round) {
      if (round > static_cast<int>(n) + 10) throw Error("internal: the fork joins did not settle");
      clusters_.clear();
      for (NodeId v = 0; v < n; ++v)
        if (is_junction_[v] && !(t_.chain_of[v] >= 0 && absorbed_[static_cast<std::size_t>(t_.chain_of[v])]))
          clusters_[uf.find(v)].nodes.push_back(v);
      // A fork merged into another's join whose own branches have all been left out since is a fork
      // no longer: the chain to it ends there in a tip. The merged hull holds no ring at it, and the
      // chain went with it (0.39 m of AdTree's Lille_2, and the limbs swept apart from its end hung
      // in the air, apart from the tree).
      std::vector<std::size_t> unforked;
      for (const auto& [id, cl] : clusters_)
        if (cl.nodes.size() > 1)
          for (NodeId v : cl.nodes)
            if (bare(v)) {
              is_junction_[v] = false;
              unforked.push_back(v);
            }
      if (!unforked.empty()) {
        refresh(settled, unforked);
        continue;
      }
      collect_arms(uf);
      bool changed = false;
      std::vector<std::size_t> dirty;
      for (auto& [id, cl] : clusters_) {
        if (settled.count(id)) continue;
        const auto failed = solve(cl);
        if (!failed) {
          settled.insert(id);
          continue;
        }
        const Arm& arm = cl.arms[*failed];
        const auto& chain = t_.chains[arm.chain];
        const double length = lines_[arm.chain].length();
        if (arm.kind == Arm::leaf && length > o_.absorb_length * last_reach_ / o_.join_reach) {
          detach(arm.chain, attempt, dirty);  // a long twig whose ring does not fit: swept apart
        } else if (arm.kind == Arm::leaf) {  // a twig that never leaves the hull: the hull stands for it
          absorbed_[arm.chain] = true;
          ++attempt.absorbed;
        } else if (arm.kind == Arm::root && length > last_reach_ &&
                   cl.arms[last_partner_].kind != Arm::root) {
          // The base is far from this join: the branch whose ring would not let the base's ring fit
          // is swept apart, rather than the hull reaching down to the base.
          detach(cl.arms[last_partner_].chain, attempt, dirty);
        } else if (arm.kind == Arm::inner) {
          if (!compact_merge(uf, chain.nodes.front(), chain.nodes.back()) && thin_or_drop(arm.chain, attempt, dirty)) {
            changed = true;  // the upper branch was thinned or left out rather than bulge a hull
            continue;
          }
          if (uf.unite(chain.nodes.front(), chain.nodes.back())) ++attempt.merged_forks;
          dirty.push_back(chain.nodes.front());
        } else {  // the root chain is too short: the root joins the hull, which closes the base
          is_junction_[sk_.root] = true;
          uf.unite(chain.nodes.back(), sk_.root);
          dirty.push_back(sk_.root);
        }
        changed = true;
      }
      refresh(settled, dirty);
      if (changed) continue;
      // Settled joins were skipped above, and their arms were collected afresh: place their rings.
      bool all = true;
      for (auto& [id, cl] : clusters_)
        if (solve(cl)) {
          settled.erase(id);
          all = false;
        }
      if (!all) continue;
      // The rings at both ends of a chain must leave room between them and must not cross.
      for (std::size_t c = 0; c < t_.chains.size(); ++c) {
        const auto& chain = t_.chains[c];
        const NodeId a = chain.nodes.front(), b = chain.nodes.back();
        const bool ja = is_junction_[a], jb = is_junction_[b];
        if (absorbed_[c] || (ja && jb && uf.find(a) == uf.find(b))) continue;
        const Polyline& pl = lines_[c];
        const double s0 = ja ? ring_d_[c][0] : 0.0;
        const double s1 = jb ? pl.length() - ring_d_[c][1] : tip_arc(pl, s0);
        Ring first = ring_at(pl, s0, sides_[c]), last = ring_at(pl, s1, sides_[c]);
        first.radius *= ja ? ring_neck_[c][0] : 1.0;
        last.radius *= jb ? ring_neck_[c][1] : 1.0;
        // A chain many radii long has room between its end rings even when it curls so that they
        // face apart: the rings laid along it in between keep its tube from crossing itself. Between
        // two forks, where it may be swept straight instead, those rings are laid here to see (a
        // chain that doubles back within a few of its radii has none that lead it round).
        const double room = s1 - s0;
        std::vector<Ring> rings;
        if (room > kLeastRoomShare * pl.length() &&
            (compatible(first, last, eps_) ||
             (room > kRoomyChain * std::max(first.radius, last.radius) &&
              (!(ja && jb) || straightened_[c] || lay_rings(pl, s0, s1, first, last, sides_[c], rule_, rings)))))
          continue;
        if (ja && jb && !compact_merge(uf, a, b)) {
          if (!straightened_[c] && pl.p.size() > 2) {
            // Forks too far apart for one join, and no tube along the chain between them (most
            // often the skeleton wandering: it doubles back within a few of its radii): the chain
            // is first swept straight from fork to fork, bent rather than thinned with all it
            // carries, which may be most of the crown; thinned only if that does not fit either.
            straightened_[c] = true;
            const Polyline bent = pl;
            lines_[c] = make_polyline({bent.p.front(), bent.p.back()}, {bent.r.front(), bent.r.back()}, eps_);
            ++attempt.straightened;
            settled.erase(uf.find(a));
            settled.erase(uf.find(b));
            all = false;
            continue;
          }
          std::vector<std::size_t> touched;
          if (thin_or_drop(c, attempt, touched)) {  // the upper branch was thinned or left out
            for (std::size_t v : touched) settled.erase(uf.find(v));
            all = false;
            continue;
          }
        }
        if (ja && jb) {  // two forks too close for a branch between them: one join
          settled.erase(uf.find(a));
          settled.erase(uf.find(b));
          if (uf.unite(a, b)) ++attempt.merged_forks;
        } else if (ja) {  // a twig that cannot leave its join
          absorbed_[c] = true;
          ++attempt.absorbed;
          settled.erase(uf.find(a));
        } else {  // the root chain: the root joins the hull
          is_junction_[sk_.root] = true;
          uf.unite(b, sk_.root);
          settled.erase(uf.find(b));
        }
        all = false;
      }
      if (all) break;
      refresh(settled, {});
    }
    build(uf, attempt);
    return attempt;
  }

 private:
  /// The arms of every join: the chains with exactly one end in it.
  void collect_arms(UnionFind& uf) {
    for (std::size_t c = 0; c < t_.chains.size(); ++c) {
      if (absorbed_[c]) continue;
      const auto& chain = t_.chains[c];
      const NodeId a = chain.nodes.front(), b = chain.nodes.back();
      const std::ptrdiff_t ca = is_junction_[a] ? static_cast<std::ptrdiff_t>(uf.find(a)) : -1;
      const std::ptrdiff_t cb = is_junction_[b] ? static_cast<std::ptrdiff_t>(uf.find(b)) : -1;
      if (ca == cb) continue;  // inside one join (or a lone chain from the root to a tip)
      const double length = lines_[c].length();
      for (const bool forward : {true, false}) {
        const std::ptrdiff_t here = forward ? ca : cb, there = forward ? cb : ca;
        if (here < 0) continue;
        Arm arm;
        arm.chain = c;
        arm.forward = forward;
        if (there >= 0) {
          arm.kind = Arm::inner;  // its room is set by solve(), from what the other join leaves
        } else if (forward) {
          arm.kind = Arm::leaf;
          arm.available = kTwigRoom * length;
        } else {
          arm.kind = Arm::root;
          arm.available = kBaseRoom * length;
        }
        clusters_[static_cast<std::size_t>(here)].arms.push_back(arm);
      }
    }
  }

  /// Ring of an arm at distance d from its join, and its outward normal.
  std::pair<Ring, Vector3d> arm_ring(const Arm& arm, double d) const {
    return detail::arm_ring(arm, d, lines_[arm.chain], sides_[arm.chain]);
  }

  /// Pushes each arm's ring out until every ring's plane has all other rings behind it. Returns the
  /// arm that ran out of length, if one did.
  std::optional<std::size_t> solve(Cluster& cl) {
    const std::size_t k = cl.arms.size();
    double r_max = 0.0;
    for (auto& arm : cl.arms) {
      const Polyline& pl = lines_[arm.chain];
      // An inner chain is shared with the join at its other end.
      if (arm.kind == Arm::inner) arm.available = kInnerRoom * pl.length() - ring_d_[arm.chain][arm.forward ? 1 : 0];
      arm.neck = 1.0;
      r_max = std::max(r_max, arm.forward ? pl.r.front() : pl.r.back());
    }
    const double reach = o_.join_reach * r_max;
    std::vector<std::size_t> partner(k, 0);  // the arm whose ring most crosses each arm's plane
    for (int neck_round = 0;; ++neck_round) {
      const auto failed = place_rings(cl, reach, lines_, sides_, eps_, partner);
      if (!failed) {
        for (const auto& arm : cl.arms) {
          ring_d_[arm.chain][arm.forward ? 0 : 1] = arm.d;
          ring_neck_[arm.chain][arm.forward ? 0 : 1] = arm.neck;
        }
        return std::nullopt;
      }
      const std::size_t i = *failed, j = partner[i];
      last_reach_ = reach;
      const bool short_twig = cl.arms[i].kind == Arm::leaf && cl.arms[i].available < reach;
      if (!short_twig && neck_round < o_.max_necks) {
        // A narrow fork: both arms are thinned where they meet, so that their rings clear each
        // other close to the fork.
        cl.arms[i].neck *= kNeckFactor;
        cl.arms[j].neck *= kNeckFactor;
        continue;
      }
      // A twig is given up before two joins are merged.
      if (cl.arms[i].kind != Arm::leaf && cl.arms[j].kind == Arm::leaf) {
        last_partner_ = i;
        return j;
      }
      last_partner_ = j;
      return i;
    }
  }


  /// Whether the joins of forks `a` and `b` would, merged, still span at most `join_reach` radii
  /// of their thickest branch.
  bool compact_merge(UnionFind& uf, NodeId a, NodeId b) {
    const std::size_t ra = uf.find(a), rb = uf.find(b);
    std::vector<NodeId> forks;
    const auto ca = clusters_.find(ra), cb = clusters_.find(rb);
    if (ca != clusters_.end() && cb != clusters_.end()) {  // as the round found them
      forks = ca->second.nodes;
      forks.insert(forks.end(), cb->second.nodes.begin(), cb->second.nodes.end());
    } else {
      for (NodeId v = 0; v < is_junction_.size(); ++v)
        if (is_junction_[v] && (uf.find(v) == ra || uf.find(v) == rb)) forks.push_back(v);
    }
    double r_max = 0.0;
    for (NodeId v : forks) r_max = std::max(r_max, sk_[v].radius);
    for (std::size_t i = 0; i < forks.size(); ++i)
      for (std::size_t j = i + 1; j < forks.size(); ++j)
        if ((sk_[forks[i]].position - sk_[forks[j]].position).norm() > o_.join_reach * r_max) return false;
    return true;
  }

  NodeId chain_top(std::size_t c) const { return t_.chains[c].nodes[1]; }

  /// Chain `c` and every chain it carries.
  std::vector<std::size_t> carried_chains(std::size_t c) const {
    std::vector<std::size_t> chains{c};
    for (std::size_t i = 0; i < chains.size(); ++i)
      for (std::size_t child : t_.chains[chains[i]].children) chains.push_back(child);
    return chains;
  }

  /// The joins at both ends of chain `c` cannot both fit. A branch is swept apart with all it
  /// carries, at its own radii, for `sweep_mesh` to unite with the tree: thinning it with all it
  /// carries, up to three times, left a limb that carries much of the crown a third of its radius
  /// (AdTree's tree1 lost 8% of its volume so). The chain from the root, which may not go, is thinned
  /// (x repair_shrink, up to max_shrinks times). Appends the forks whose joins must be placed again
  /// to `touched`. False for the root chain thinned as far as it may be (its forks are then merged).
  bool thin_or_drop(std::size_t c, Attempt& attempt, std::vector<std::size_t>& touched) {
    if (t_.chains[c].nodes.front() != sk_.root) {
      detach(c, attempt, touched);
      return true;
    }
    if (thinned_[c] >= o_.max_shrinks) return false;
    ++thinned_[c];
    ++attempt.thinned;
    const auto chains = carried_chains(c);
    for (std::size_t d : chains)
      for (double& r : lines_[d].r) r *= o_.repair_shrink;
    for (std::size_t d : chains) touched.insert(touched.end(), {t_.chains[d].nodes.front(), t_.chains[d].nodes.back()});
    return true;
  }

  /// Whether every branch leaving fork `v` has been left out of this sweep (swept apart, or inside a
  /// join).
  bool bare(NodeId v) const {
    if (v == sk_.root || t_.chain_of[v] < 0) return false;
    const auto& leaving = t_.chains[static_cast<std::size_t>(t_.chain_of[v])].children;
    return std::all_of(leaving.begin(), leaving.end(), [&](std::size_t c) { return absorbed_[c]; });
  }

  /// Leaves chain `c` and all it carries out of this sweep, for `sweep_mesh` to sweep apart and
  /// unite; the joins at its ends are placed again.
  void detach(std::size_t c, Attempt& attempt, std::vector<std::size_t>& touched) {
    ++attempt.dropped;
    attempt.detached.push_back(chain_top(c));
    for (std::size_t d : carried_chains(c)) {
      absorbed_[d] = true;
      touched.insert(touched.end(), {t_.chains[d].nodes.front(), t_.chains[d].nodes.back()});
    }
  }

  void build(UnionFind& uf, Attempt& attempt) {
    std::vector<Vector3d>& vertices = attempt.vertices;
    // Rings at the joins, keyed by (chain, at its start?).
    struct JoinRing {
      double arc;
      std::size_t first_vertex;
      Ring ring;
      std::size_t join;
    };
    std::map<std::pair<std::size_t, bool>, JoinRing> join_ring;
    std::vector<Join> joins;
    for (auto& [id, cl] : clusters_) {
      if (cl.arms.empty()) continue;  // a fork inside a branch that was left out
      ++attempt.junctions;
      Join join;
      join.top = cl.nodes.front();
      for (const auto& arm : cl.arms) {
        const Polyline& pl = lines_[arm.chain];
        const double arc = arm.forward ? arm.d : pl.length() - arm.d;
        const Ring ring = arm_ring(arm, arm.d).first;
        join.rings.push_back(ring);
        join.first_vertex.push_back(detail::add_ring(vertices, ring));
        join_ring[{arm.chain, arm.forward}] = {arc, join.first_vertex.back(), ring, joins.size()};
        join.radius = std::max(join.radius, ring.radius / arm.neck);  // the branch's, not its neck's
        if (!arm.forward) join.top = t_.chains[arm.chain].nodes.back();
      }
      if (std::none_of(cl.arms.begin(), cl.arms.end(), [](const Arm& a) { return !a.forward; })) join.top = sk_.root;
      const bool based = is_junction_[sk_.root] && uf.find(sk_.root) == id && add_base(cl, join, vertices);
      if (cl.arms.size() == 1 && !based) {  // every other arm left inside: a cone closes the branch
        const auto [ring, outward] = arm_ring(cl.arms.front(), cl.arms.front().d);
        vertices.push_back(ring.centre - outward * std::max(kConeRadii * ring.radius, cl.arms.front().d));
        join.points.emplace_back(vertices.back(), vertices.size() - 1);
      }
      joins.push_back(std::move(join));
    }
    // Tubes.
    std::vector<Tube> tubes;
    for (std::size_t c = 0; c < t_.chains.size(); ++c) {
      const auto& chain = t_.chains[c];
      const NodeId a = chain.nodes.front(), b = chain.nodes.back();
      if (absorbed_[c]) continue;
      if (is_junction_[a] && is_junction_[b] && uf.find(a) == uf.find(b)) continue;  // inside a join
      ++attempt.branches;
      const Polyline& pl = lines_[c];
      const int sides = sides_[c];
      Tube tube;
      tube.owner = chain_top(c);
      // First ring: at the join, or at the root with a flat base cap.
      double s0 = 0.0;
      Ring first;
      if (is_junction_[a]) {
        const JoinRing& j = join_ring.at({c, true});
        s0 = j.arc;
        tube.first_vertex = j.first_vertex;
        tube.start_join = static_cast<std::ptrdiff_t>(j.join);
        first = j.ring;
      } else {
        tube.base = true;
        first = ring_at(pl, 0.0, sides);
        tube.base_centre = first.centre;
        if (base_ == detail::BaseCap::hidden) {
          Vector3d aside = pl.p.back() - first.centre;
          aside -= aside.dot(first.normal) * first.normal;
          const double n = aside.norm();
          if (n > eps_) aside /= n;
          else aside.setZero();
          // Turned about the axis: two limbs that leave a fork as mirror images would otherwise have
          // mirror-image apexes, and a ring edge across the mirror would lie in both cones' faces.
          aside = std::cos(kHiddenBaseTurn) * aside + std::sin(kHiddenBaseTurn) * first.normal.cross(aside);
          tube.base_centre += first.radius * (kHiddenBaseAside * aside + kHiddenBaseDepth * first.normal);
        }
      }
      // Last ring: at the join, or before the tip.
      double s1;
      Ring last;
      tube.tip = !is_junction_[b];
      if (!tube.tip) {
        const JoinRing& j = join_ring.at({c, false});
        s1 = j.arc;
        tube.last_vertex = j.first_vertex;
        tube.end_join = static_cast<std::ptrdiff_t>(j.join);
        last = j.ring;
      } else {
        s1 = tip_arc(pl, s0);
        last = ring_at(pl, s1, sides);
      }
      // Rings in between, wherever the branch has run or turned enough, none crossing the last.
      std::vector<Ring>& rings = tube.rings;
      if (!lay_rings(pl, s0, s1, first, last, sides, rule_, rings)) {
        attempt.shrink.push_back(chain_top(c));
        continue;
      }
      rings.push_back(last);
      if (tube.tip) tube.apex_height = std::max((pl.p.back() - last.centre).dot(last.normal), kConeRadii * last.radius);
      tubes.push_back(std::move(tube));
    }
    if (!attempt.shrink.empty()) return;
    tessellate(joins, tubes, *hulls_, attempt);
  }

  /// The join that holds the root is closed there by a flat base across its thickest branch, as the
  /// base of a root with one branch is: its rings alone leave the tree standing on their hull, up to
  /// `join_reach` radii above its base (0.12 m of a 0.17 m trunk on plantscan3d's A3B4), and a limb
  /// swept apart from the root then hangs beneath the tree, apart from it. The base is that branch's
  /// ring (without a neck) at the root, across the branch, where it lies wholly behind every ring's
  /// plane, so that each ring stays a face of the hull; else a narrower one, else the root alone; else
  /// none (a ring leaning over the root). Its points are optional points of `join.points`: those the
  /// hull leaves inside it (where a ring dips below the base) are left out.
  bool add_base(const Cluster& cl, Join& join, std::vector<Vector3d>& vertices) const {
    // The thickest branch, by its radius without the neck its ring may have at a narrow fork.
    auto width = [&](std::size_t i) { return join.rings[i].radius / cl.arms[i].neck; };
    std::size_t thick = 0;
    for (std::size_t i = 1; i < join.rings.size(); ++i)
      if (width(i) > width(thick)) thick = i;
    const auto [widest, outward] = arm_ring(cl.arms[thick], cl.arms[thick].d);
    Ring base;
    base.centre = sk_[sk_.root].position;
    base.normal = -outward;
    base.u = widest.u;
    base.sides = widest.sides;
    for (const double share : kBaseCapShares) {
      base.radius = share * width(thick);
      if (!behind_rings(cl, base)) continue;
      for (int k = 0; k < (share > 0.0 ? base.sides : 1); ++k) {
        vertices.push_back(share > 0.0 ? base.vertex(k) : base.centre);
        join.points.emplace_back(vertices.back(), vertices.size() - 1);
        ++join.optional;
      }
      return true;
    }
    return false;
  }

  /// Whether `circle` (a ring, or a point: radius 0) lies wholly behind the plane of every ring of
  /// the join `cl`, by the margin `place` leaves between rings.
  bool behind_rings(const Cluster& cl, const Ring& circle) const {
    return std::all_of(cl.arms.begin(), cl.arms.end(), [&](const Arm& arm) {
      const auto [ring, out] = arm_ring(arm, arm.d);
      return reach_beyond(ring, out, circle) < -(kRingClearanceRadii * ring.radius + eps_);
    });
  }

  const Skeleton& sk_;
  const SweepOptions& o_;
  ChainTree t_;
  HullCache* hulls_;
  detail::RingRule rule_;  // where a tube lays its rings
  double eps_ = 0.0;
  std::vector<Polyline> lines_;
  std::vector<int> sides_;
  std::vector<bool> is_junction_;
  std::vector<int> thinned_;  // per chain: times thinned in this build
  std::vector<bool> straightened_;  // per chain: swept straight from fork to fork in this build
  std::vector<std::pair<NodeId, NodeId>> fused_;
  detail::BaseCap base_;
  double max_radius_ = 0.0;
  std::vector<bool> absorbed_;  // per chain: a twig left inside its join's hull
  std::vector<std::array<double, 2>> ring_neck_;  // per chain: neck factor of those rings
  std::vector<std::array<double, 2>> ring_d_;  // per chain: ring distance from its start's join, its end's join
  std::map<std::size_t, Cluster> clusters_;
  double last_reach_ = 0.0;         // reach of the join `solve` last failed at
  std::size_t last_partner_ = 0;    // the arm whose ring the failed arm's could not clear
};

/// Sweeps what of `skeleton` fits together into one valid mesh. Subtrees that a join or a crossing
/// left no room for are not swept here: their nodes go to `detached`, for `sweep_mesh` to sweep
/// apart and unite with this mesh. `swept` tells, by node, whether the mesh holds it.
TreeMesh sweep_attached(const Skeleton& skeleton, const SweepOptions& options, const Vector3d& frame, const detail::TreeScale& whole,
                        SweepStats& st, std::vector<NodeId>& detached, std::vector<char>& swept, detail::BaseCap base) {
  const ChainTree tree = build_chains(skeleton);
  const auto& g = skeleton.graph;
  const std::size_t n = boost::num_vertices(g);
  double max_radius = 0.0;
  for (NodeId v = 0; v < n; ++v) max_radius = std::max(max_radius, g[v].radius);
  // The wood a branch carries is its own frustums and all those above it, at the skeleton's radii.
  detail::Thinning thinning(skeleton, tree, options, whole, edge_wood(skeleton, tree, whole.floor_radius), st, detached);
  const auto& keep = thinning.keep();
  const auto& scale = thinning.scale();
  const double thinnest = std::max(options.min_radius, options.min_relative_radius * max_radius);
  for (const auto& c : tree.chains)
    if (keep[c.nodes[1]] && g[c.nodes[1]].radius < thinnest && c.nodes[1] != skeleton.root) {
      thinning.drop(c.nodes[1]);
      ++st.thin_left_out;
    }
  if (!keep[tree.chains.front().nodes[1]] && tree.children[skeleton.root].size() == 1)
    throw InputError("every branch is thinner than the minimum radius; nothing is left to mesh");

  Builder::HullCache hulls;
  const int max_attempts = 4 * static_cast<int>(n) + 50;
  std::optional<TreeMesh> best;
  for (int attempt_no = 0; attempt_no < max_attempts; ++attempt_no) {
    // The kept, scaled skeleton.
    Skeleton pruned = skeleton;  // positions, radii and edges only (see sweep_mesh)
    for (NodeId v = 0; v < n; ++v) pruned[v].radius *= scale[v];
    const auto new_id = compact_nodes(pruned, keep);
    std::vector<NodeId> old_id(boost::num_vertices(pruned.graph));
    for (NodeId v = 0; v < n; ++v)
      if (new_id[v] >= 0) old_id[static_cast<std::size_t>(new_id[v])] = v;
    if (boost::num_vertices(pruned.graph) < 2) throw InputError("nothing is left to mesh after leaving out branches");
    if (options.narrow_angle > 0.0) {
      std::size_t moved = 0;
      const auto relocated = relocate_narrow_branches(pruned, options.narrow_angle, moved);
      std::vector<NodeId> composed(boost::num_vertices(pruned.graph));
      for (std::size_t v = 0; v < relocated.size(); ++v)
        if (relocated[v] >= 0) composed[static_cast<std::size_t>(relocated[v])] = old_id[v];
      old_id = std::move(composed);
      st.relocated_branches = moved;
    }

    ++st.attempts;
    // The subtrees the builder left out, as it saw them: a branch re-attached to a thicker one hangs
    // from it there, so the whole subtree under each top (in `pruned`) goes, mapped back.
    // The nodes the mesh holds: those of `pruned` the builder did not leave out.
    auto record_detached = [&](const Skeleton& p, const std::vector<NodeId>& ids, const std::vector<NodeId>& tops) {
      const std::size_t first = detached.size();
      if (!tops.empty()) {
        const ChainTree pt = build_chains(p);
        for (NodeId top : tops)
          for (NodeId v : subtree(pt.children, top)) detached.push_back(ids[v]);
      }
      swept.assign(n, 0);
      for (NodeId v : ids) swept[v] = 1;
      for (std::size_t i = first; i < detached.size(); ++i) swept[detached[i]] = 0;
    };
    std::vector<std::int64_t> pruned_of(n, -1);
    for (std::size_t v = 0; v < old_id.size(); ++v) pruned_of[old_id[v]] = static_cast<std::int64_t>(v);
    std::vector<std::pair<NodeId, NodeId>> fuse;
    for (const auto& [x, y] : thinning.fused())
      if (pruned_of[x] >= 0 && pruned_of[y] >= 0)
        fuse.emplace_back(static_cast<NodeId>(pruned_of[x]), static_cast<NodeId>(pruned_of[y]));
    Builder builder(pruned, options, hulls, whole.longest_band, std::move(fuse), base);
    Attempt a = builder.run();
    st.branches = a.branches;
    st.junctions = a.junctions;
    st.merged_forks = a.merged_forks;
    st.straightened_branches = a.straightened;
    st.twigs_absorbed = a.absorbed;
    st.joins_thinned = a.thinned;
    st.joins_dropped = a.dropped;
    if (!a.shrink.empty()) {
      thinning.shrink_failed(a.shrink, old_id);
      continue;
    }
    // Crossings are found and repaired on the triangles first (cheap: only parts whose boxes overlap
    // are tested); CGAL's test of the whole mesh then confirms the result, or starts another round.
    const bool may_repair = options.repair && st.repair_rounds < options.repair_rounds;
    if (may_repair) {
      const auto crossing = crossing_parts(a);
      if (!crossing.empty() && thinning.repair(crossing, true, a, old_id)) continue;
    }
    std::optional<TreeMesh> mesh = assemble(a);
    if (!mesh) {
      thinning.shrink_failed(a.shrink, old_id);
      continue;
    }
    if (!options.repair) {
      best = std::move(mesh);
      record_detached(pruned, old_id, a.detached);
      break;
    }
    // Tested in the 32-bit floats of the frame files hold (where rounding can fold the needle-thin
    // faces of a twig's tip into each other), then in doubles (what OBJ holds). CGAL's test runs on
    // one core here, so the two run side by side; the doubles' answer counts only when the floats
    // found nothing.
    std::vector<std::pair<std::size_t, std::size_t>> pairs, double_pairs;
    const auto tested = std::chrono::steady_clock::now();
    tbb::parallel_invoke([&] { pairs = self_intersecting_faces_at(*mesh, detail::world_floats(*mesh, frame)); },
                         [&] { double_pairs = self_intersecting_faces(*mesh); });
    st.test_seconds += detail::seconds_since(tested);
    st.float_crossings = pairs.size();
    if (pairs.empty()) pairs = std::move(double_pairs);
    st.self_intersections = pairs.size();
    if (pairs.empty() || !may_repair) {
      best = std::move(mesh);
      record_detached(pruned, old_id, a.detached);
      break;
    }
    ++st.late_repair_rounds;
    if (!thinning.repair(pairs, false, a, old_id)) {
      best = std::move(mesh);
      record_detached(pruned, old_id, a.detached);
      break;
    }
  }
  if (!best) throw Error("could not build a valid mesh of this skeleton");
  return std::move(*best);
}

}  // namespace

void check_sweep_options(const SweepOptions& options) {
  if (options.min_segments < 3 || options.max_segments < options.min_segments || options.trunk_segments < 3)
    throw OptionError("segments around a branch: need 3 <= min <= max and at least 3 around the trunk");
  if (options.min_radius < 0.0 || options.min_relative_radius < 0.0 || options.min_relative_radius >= 1.0)
    throw OptionError("the minimum branch radius must not be negative (and the relative one below 1)");
  if (!(options.ring_spacing > 0.0) || !(options.max_turn > 0.0)) throw OptionError("ring spacing and turn must be positive");
  if (!(options.repair_shrink > 0.0 && options.repair_shrink < 1.0)) throw OptionError("the repair shrink factor must be in (0, 1)");
  if (!(options.max_thinned_share >= 0.0)) throw OptionError("the share of the wood a thinned branch may carry must not be negative");
}

Eigen::Vector3d detail::file_frame(const Skeleton& skeleton) {
  Eigen::AlignedBox3d box;
  for (NodeId v = 0; v < boost::num_vertices(skeleton.graph); ++v) box.extend(skeleton[v].position);
  // The input's, unless 32-bit floats would round it by more than 1e-5 of the tree's size (a
  // georeferenced tree), when files hold local coordinates (io/mesh_io.h).
  const double far =
      (box.min() + skeleton.offset).cwiseAbs().cwiseMax((box.max() + skeleton.offset).cwiseAbs()).maxCoeff();
  return far * std::ldexp(1.0, -24) > 1e-5 * box.sizes().maxCoeff() ? Eigen::Vector3d::Zero() : skeleton.offset;
}

TreeMesh sweep_mesh(const Skeleton& skeleton, const SweepOptions& options, SweepStats* stats) {
  check_sweep_options(options);
  if (boost::num_vertices(skeleton.graph) < 2) throw InputError("the skeleton has no branch to sweep (a single node)");
  const Eigen::Vector3d frame = options.local_floats ? Eigen::Vector3d::Zero() : detail::file_frame(skeleton);
  return detail::sweep_in_frame(skeleton, options, frame, -1.0, stats);
}

namespace {

/// `shape` without the nodes `taken` (into pieces). A branch the mesh holds whose parent went into a
/// piece (the builder re-attached it to a thicker branch) hangs from the nearest node left, as
/// the builder hung it: the part stays one tree, for `split_piece`.
Skeleton kept_part(const Skeleton& shape, const ChainTree& tree, const std::vector<bool>& taken) {
  const std::size_t n = taken.size();
  Skeleton kept = shape;
  std::vector<bool> keep(n);
  for (NodeId v = 0; v < n; ++v) keep[v] = !taken[v];
  for (NodeId v = 0; v < n; ++v) {
    if (!keep[v] || v == shape.root || keep[tree.parent[v]]) continue;
    std::vector<bool> own(n, false);
    for (NodeId u : subtree(tree.children, v)) own[u] = true;
    NodeId nearest = shape.root;  // never taken, and not above v
    double best = std::numeric_limits<double>::infinity();
    for (NodeId u = 0; u < n; ++u) {
      const double d = (shape[u].position - shape[v].position).squaredNorm();
      if (keep[u] && !own[u] && d < best) {
        best = d;
        nearest = u;
      }
    }
    boost::remove_edge(tree.parent[v], v, kept.graph);
    boost::add_edge(nearest, v, kept.graph);
  }
  compact_nodes(kept, keep);
  return kept;
}

}  // namespace

TreeMesh detail::sweep_part(const Skeleton& skeleton, const SweepOptions& options, const Eigen::Vector3d& frame,
                            const TreeScale& scale, SweepStats& st, std::vector<Skeleton>& apart, Skeleton* kept,
                            BaseCap base) {
  const ChainTree tree = build_chains(skeleton);
  const auto& g = skeleton.graph;
  const std::size_t n = boost::num_vertices(g);
  if (n < 2) throw InputError("the skeleton has no branch to sweep (a single node)");
  double max_radius = 0.0;
  for (NodeId v = 0; v < n; ++v) {
    if (!(g[v].radius > 0.0) || !std::isfinite(g[v].radius))
      throw InputError("skeleton node " + std::to_string(v) + " has radius " + std::to_string(g[v].radius) +
                       "; every radius must be positive (fit the radii first)");
    max_radius = std::max(max_radius, g[v].radius);
  }

  // The sweep needs positions, radii and edges only; radii under the floor are raised to it.
  const double floor = scale.floor_radius;
  Skeleton shape;
  shape.root = skeleton.root;
  shape.offset = skeleton.offset;
  for (NodeId v = 0; v < n; ++v) {
    SkeletonNode node;
    node.position = g[v].position;
    node.radius = g[v].radius;
    if (node.radius < floor) {
      node.radius = floor;
      ++st.raised_to_floor;
    }
    add_node(shape, node);
  }
  for (auto [it, end] = boost::edges(g); it != end; ++it) boost::add_edge(boost::source(*it, g), boost::target(*it, g), shape.graph);
  SweepOptions o = options;
  o.min_relative_radius = 0.0;  // applied above, once for the whole tree

  std::vector<NodeId> detached;
  std::vector<char> swept;
  TreeMesh mesh = sweep_attached(shape, o, frame, scale, st, detached, swept, base);
  if (!detached.empty() && !options.unite_apart) {
    std::vector<bool> cut(n, false);
    for (NodeId v : detached) cut[v] = true;
    for (NodeId v = 0; v < n; ++v)
      if (cut[v] && !cut[tree.parent[v]]) ++st.pieces_failed;  // left out, as asked
  } else if (!detached.empty()) {
    // Each subtree left out above is swept on its own, and the pieces are united with the mesh: a
    // limb is never lost for want of room at a join. One piece per branch, none inside another's,
    // none holding what the mesh holds: a branch the builder re-attached to a thicker one (see
    // relocate_narrow_branches) stays in the mesh when the branch it left goes. (Taken with that
    // branch's subtree, an 8,614-node limb of a pine of the LPine1 plot was swept twice, in the
    // mesh and in a piece, and the unions ran for six minutes on the crossings of the two copies.)
    std::vector<bool> cut(n, false), taken(n, false);
    for (NodeId v : detached) cut[v] = true;
    std::vector<NodeId> tops;  // the first node of each subtree left out
    for (NodeId v = 0; v < n; ++v)
      if (cut[v] && v != shape.root && !cut[tree.parent[v]]) tops.push_back(v);
    std::stable_sort(tops.begin(), tops.end(), [&](NodeId a, NodeId b) { return tree.chain_of[a] < tree.chain_of[b]; });
    // Each stub is checked against the mesh its parent went into (see piece_of).
    std::optional<detail::MeshDepth> in_mesh;
    const detail::DepthTest depth = [&](const Vector3d& p) {
      if (!in_mesh) in_mesh.emplace(mesh);
      return (*in_mesh)(p);
    };
    const detail::NearestTest nearest = [&](const Vector3d& p) {
      if (!in_mesh) in_mesh.emplace(mesh);
      return in_mesh->nearest(p);
    };
    for (NodeId top : tops) {
      if (taken[top]) continue;
      std::vector<NodeId> members;
      apart.push_back(piece_of(shape, tree, top, depth, &swept, &members, nearest));
      for (NodeId v : members) taken[v] = true;
    }
    if (kept) *kept = kept_part(shape, tree, taken);
    return mesh;
  }
  if (kept) *kept = shape;
  return mesh;
}

TreeMesh detail::sweep_in_frame(const Skeleton& skeleton, const SweepOptions& options, const Eigen::Vector3d& frame,
                                double floor_radius, SweepStats* stats) {
  double max_radius = 0.0;
  Eigen::AlignedBox3d box;
  for (NodeId v = 0; v < skeleton.node_count(); ++v) {
    if (std::isfinite(skeleton[v].radius)) max_radius = std::max(max_radius, skeleton[v].radius);
    box.extend(skeleton[v].position);
  }
  // Raised to the floor: a share of the thickest radius, or of the tree's extent.
  if (floor_radius < 0.0)
    floor_radius = std::max(options.min_relative_radius * max_radius, options.min_extent_radius * box.sizes().maxCoeff());
  const TreeScale scale{floor_radius, options.max_drop_radius * std::max(max_radius, floor_radius),
                        wood_volume(skeleton, floor_radius), kLongestBandShare * box.sizes().maxCoeff()};
  SweepStats st;
  std::vector<Skeleton> apart;
  const auto start = std::chrono::steady_clock::now();
  TreeMesh mesh = sweep_part(skeleton, options, frame, scale, st, apart, nullptr);
  st.sweep_seconds = detail::seconds_since(start);
  if (!apart.empty()) mesh = add_pieces(std::move(mesh), apart, options, frame, scale, st);
  if (stats) *stats = st;
  return mesh;
}

}  // namespace treeskel::modeling


