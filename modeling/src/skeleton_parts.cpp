#include "skeleton_parts.h"

#include "treeskel/geometry.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>

namespace treeskel::modeling::detail {

namespace {

using Eigen::Vector3d;

/// How far, in fork radii, a piece's stub follows its parent's path back from the fork.
constexpr double kStubReach = 4.0;
/// How many of the parent's nodes the stub of a piece that would not meet the parent's mesh may
/// follow back to find the mesh.
constexpr int kStubNodes = 8;
/// At most this many points along a segment are tested for whether a piece's tube meets a mesh.
constexpr int kMeetSamples = 32;
/// Grid points a side, from the fork out, searched for where to end the stub of a piece that meets
/// the parent's mesh nowhere.
constexpr int kStubGrid = 4;

/// Distance from `p` to the polyline through `nodes`.
double distance_to_polyline(const Skeleton& sk, const std::vector<NodeId>& nodes, const Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < nodes.size(); ++i)
    best = std::min(best, point_segment_distance(p, sk[nodes[i]].position, sk[nodes[i + 1]].position));
  return best;
}

/// Unit direction from the first node of `nodes` to the point `arc` along them.
Vector3d direction_along(const Skeleton& sk, const std::vector<NodeId>& nodes, double arc) {
  double run = 0.0;
  for (std::size_t i = 1; i < nodes.size(); ++i) {
    run += (sk[nodes[i]].position - sk[nodes[i - 1]].position).norm();
    if (run >= arc || i + 1 == nodes.size()) {
      const Vector3d d = sk[nodes[i]].position - sk[nodes.front()].position;
      return d.norm() > 0.0 ? Vector3d(d.normalized()) : Vector3d::Zero();
    }
  }
  return Vector3d::Zero();
}

/// Calls `visit(point, distance)` for each point of a grid of 2 kStubGrid + 1 points a side around
/// `centre`, `reach` / kStubGrid apart, that lies within `reach` of it, x, then y, then z ascending.
template <class Visit>
void for_stub_grid(const Vector3d& centre, double reach, Visit&& visit) {
  const double step = reach / kStubGrid;
  for (int x = -kStubGrid; x <= kStubGrid; ++x)
    for (int y = -kStubGrid; y <= kStubGrid; ++y)
      for (int z = -kStubGrid; z <= kStubGrid; ++z) {
        const Vector3d offset = step * Vector3d(x, y, z);
        const double distance = offset.norm();
        if (distance <= reach * (1.0 + 1e-9)) visit(Vector3d(centre + offset), distance);
      }
}

/// The turns of a piece's axis its tube is taken to cut across when testing whether the tube meets
/// the mesh (see piece_of), as the greatest cosine between the directions in and out: 90 degrees.
constexpr double kCutTurnCos = 0.0;

/// The turn into the branch a stub may make at its fork, as the least cosine between the stub's
/// direction and the branch's: 117 degrees, short of the 120 the tube drops (see tube.h).
constexpr double kStubTurnCos = -0.45;

/// Where a stub into the branch leaving `fork` along `ahead` may start, and how thick it may be:
/// a point from which the stub turns by at most kStubTurnCos into the branch, within `reach` of the
/// fork (as far as the stub could follow its parent: not past the fork below), inside the mesh
/// `depth` measures. Of the nodes around the fork that the mesh holds (by `swept`; not the
/// branch's, which `first` starts) and then of the points of a grid around it, the nearest that
/// lies `radius` deep, with `radius`; failing that, the deepest, with its depth as the stub's radius
/// (the sweep raises it to its floor radius); none if no such point is inside the mesh.
std::optional<std::pair<Vector3d, double>> straight_stub(const Skeleton& skeleton, const ChainTree& tree, NodeId fork,
                                                         NodeId first, const Vector3d& ahead, double radius, double reach,
                                                         const DepthTest& depth, const std::vector<char>* swept) {
  const Vector3d& at_fork = skeleton[fork].position;
  if (!(reach > 0.0)) return std::nullopt;
  std::optional<Vector3d> nearest, deepest;
  double nearest_distance = std::numeric_limits<double>::infinity(), deepest_depth = 0.0;
  auto consider = [&](const Vector3d& p) {
    const Vector3d into = at_fork - p;
    const double distance = into.norm();
    if (distance > reach || into.dot(ahead) < kStubTurnCos * distance) return;
    const double d = depth(p);
    if (d >= radius && distance < nearest_distance) {
      nearest_distance = distance;
      nearest = p;
    }
    if (d > deepest_depth) {
      deepest_depth = d;
      deepest = p;
    }
  };
  // The nodes around the fork, through the tree but not into the branch, while within reach.
  std::vector<NodeId> todo{fork};
  std::set<NodeId> seen{fork, first};
  while (!todo.empty()) {
    const NodeId v = todo.back();
    todo.pop_back();
    if (v != fork && (!swept || (*swept)[v])) consider(skeleton[v].position);
    std::vector<NodeId> next = tree.children[v];
    if (tree.parent[v] != v) next.push_back(tree.parent[v]);
    for (NodeId w : next)
      if ((skeleton[w].position - at_fork).norm() <= reach && seen.insert(w).second) todo.push_back(w);
  }
  if (!nearest)
    for_stub_grid(at_fork, reach, [&](const Vector3d& p, double distance) {
      if (distance > 0.0) consider(p);
    });
  if (nearest) return std::pair{*nearest, radius};
  if (deepest) return std::pair{*deepest, deepest_depth};
  return std::nullopt;
}

}  // namespace

std::vector<NodeId> subtree(const std::vector<std::vector<NodeId>>& children, NodeId top,
                            const std::vector<char>* skip) {
  std::vector<NodeId> out{top};
  for (std::size_t i = 0; i < out.size(); ++i)
    for (NodeId c : children[out[i]])
      if (!skip || !(*skip)[c]) out.push_back(c);
  return out;
}

std::vector<std::int64_t> relocate_narrow_branches(Skeleton& sk, double min_angle, std::size_t& moved) {
  const ChainTree t = build_chains(sk);
  const std::size_t n = boost::num_vertices(sk.graph);
  std::vector<bool> keep(n, true);
  std::vector<std::pair<NodeId, NodeId>> removed_edges, added_edges;
  std::vector<std::vector<std::size_t>> leaving(n);
  enum Role : char { none_role, moved_role, host_role };
  std::vector<Role> role(n, none_role);
  std::vector<bool> anchor(n, false);  // a moved branch hangs from it: it stays
  for (std::size_t c = 0; c < t.chains.size(); ++c) leaving[t.chains[c].nodes.front()].push_back(c);
  for (NodeId v = 0; v < n; ++v) {
    if (leaving[v].size() < 2) continue;
    // Arms from the fork outward: its chains, and the chain it ends, reversed.
    std::vector<std::vector<NodeId>> arms;
    for (std::size_t c : leaving[v]) arms.push_back(t.chains[c].nodes);
    const std::size_t children = arms.size();
    if (t.chain_of[v] >= 0) {
      const auto& in = t.chains[static_cast<std::size_t>(t.chain_of[v])].nodes;
      arms.emplace_back(in.rbegin(), in.rend());
    }
    auto radius = [&](const std::vector<NodeId>& arm) { return sk[arm[1]].radius; };
    for (std::size_t i = 0; i < children; ++i) {
      const auto& twig = arms[i];
      if (!keep[twig[1]] || role[twig[1]] == host_role) continue;
      for (std::size_t j = 0; j < arms.size(); ++j) {
        const auto& host = arms[j];
        if (j == i || radius(host) < radius(twig) || role[host[1]] == moved_role) continue;
        const double big = radius(host);
        const Vector3d a = direction_along(sk, twig, 2.0 * big), b = direction_along(sk, host, 2.0 * big);
        if (a.isZero() || b.isZero() || std::acos(std::clamp(a.dot(b), -1.0, 1.0)) >= min_angle) continue;
        // Where the twig comes out of the host's surface.
        std::size_t m = 1;
        while (m < twig.size() && distance_to_polyline(sk, host, sk[twig[m]].position) <= big + sk[twig[m]].radius) ++m;
        if (m >= twig.size() - 1 && t.children[twig.back()].empty()) break;  // a twig hidden in its host
        if (m >= twig.size()) break;
        const Vector3d q = sk[twig[m]].position;
        std::size_t k = 1;
        for (std::size_t h = 1; h < host.size(); ++h)
          if ((sk[host[h]].position - q).squaredNorm() < (sk[host[k]].position - q).squaredNorm()) k = h;
        if (!keep[host[k]]) break;
        // The stretch the twig leaves behind goes; not if another moved branch hangs from it (a
        // fork met later may move the arm that an earlier fork's twig was hung on).
        if (std::any_of(twig.begin() + 1, twig.begin() + static_cast<std::ptrdiff_t>(m), [&](NodeId h) { return anchor[h]; })) break;
        anchor[host[k]] = true;
        removed_edges.emplace_back(twig[m - 1], twig[m]);
        added_edges.emplace_back(host[k], twig[m]);
        for (std::size_t h = 1; h < m; ++h) keep[twig[h]] = false;
        // A moved branch hosts no other, and a host is not moved: no cycle can form.
        role[twig[1]] = moved_role;
        role[twig[m]] = moved_role;
        role[host[1]] = host_role;
        ++moved;
        break;
      }
    }
  }
  for (const auto& [a, b] : removed_edges) boost::remove_edge(a, b, sk.graph);
  for (const auto& [a, b] : added_edges) boost::add_edge(a, b, sk.graph);
  return compact_nodes(sk, keep);
}

Skeleton piece_of(const Skeleton& skeleton, const ChainTree& tree, NodeId top, const DepthTest& depth,
                  const std::vector<char>* swept, std::vector<NodeId>* members, const NearestTest& nearest) {
  const auto& whole_chain = tree.chains[static_cast<std::size_t>(tree.chain_of[top])].nodes;
  // From the fork, or, with `swept`, from the last node of the chain before `top` that the mesh holds.
  std::size_t start = 1;
  if (swept) {
    start = static_cast<std::size_t>(std::find(whole_chain.begin(), whole_chain.end(), top) - whole_chain.begin());
    while (start > 1 && !(*swept)[whole_chain[start - 1]]) --start;
  }
  const std::vector<NodeId> chain(whole_chain.begin() + static_cast<std::ptrdiff_t>(start - 1), whole_chain.end());
  Skeleton piece;
  piece.offset = skeleton.offset;
  std::map<NodeId, NodeId> id;
  auto add = [&](NodeId v, double radius) {
    SkeletonNode node;
    node.position = skeleton[v].position;
    node.radius = radius;
    id[v] = add_node(piece, node);
  };
  add(chain.front(), skeleton[chain[1]].radius);
  piece.root = id[chain.front()];
  // The fork may lie outside its join's hull (between rings set far apart at a narrow fork): the
  // piece starts further back, along the parent's path, which the parent's tube holds. That stub
  // is at most half as thick as the parent: as thick as the branch, a branch as thick as its
  // parent made a tube a fraction of a millimetre inside the parent's, and corefinement crawled
  // through every near-touching pair of their faces in exact arithmetic (11 of the 16 s of a pine
  // of the LPine1 plot, in one union). It follows the parent's path for `kStubReach` fork radii:
  // a stub straight back to the parent's next node (at most one radius) left the pieces of narrow
  // forks outside the parent's tube when the parent bent, and the union had nothing to join.
  const NodeId fork = chain.front();
  // With all it carries but what the mesh holds (and all that carries).
  std::vector<NodeId> branch = subtree(tree.children, chain[1], swept);
  // Toward the parent, or at a root with several branches, toward the thickest other one.
  NodeId toward = tree.parent[fork];
  const bool down = toward == fork;
  if (down)
    for (NodeId c : tree.children[fork])
      if (c != chain[1] && (toward == fork || skeleton[c].radius > skeleton[toward].radius)) toward = c;
  if (toward != fork) {
    // Up the parent's path; at a root, straight toward the other branch's next node, at most one
    // fork radius (following that branch further down set A3B4's pieces beside its stem).
    auto next_of = [&](NodeId v) { return down ? v : tree.parent[v]; };
    const double length = (down ? 1.0 : kStubReach) * skeleton[fork].radius;
    double radius = std::min(skeleton[chain[1]].radius, 0.5 * std::min(skeleton[fork].radius, skeleton[toward].radius));
    std::vector<Vector3d> path;  // from the fork back
    double walked = 0.0;
    Vector3d reached = skeleton[fork].position;
    const double enough = length * (1.0 - 1e-9);  // no sliver of a step for a rounding error
    // Not past the fork below: the stub stays on the parent's own branch.
    auto on_branch = [&](NodeId at, NodeId next) { return next != at && (at == fork || tree.children[at].size() == 1); };
    auto goes_on = [&](NodeId at, NodeId next) { return on_branch(at, next) && walked < enough; };
    for (NodeId at = fork, next = toward; goes_on(at, next); at = next, next = next_of(at)) {
      const Vector3d step = skeleton[next].position - skeleton[at].position;
      const double step_length = step.norm();
      if (step_length <= 0.0) continue;
      radius = std::min(radius, 0.5 * skeleton[next].radius);
      const double take = std::min(step_length, length - walked);
      walked += take;
      reached = skeleton[at].position + step * (take / step_length);
      // No ring closer to the fork than its radius: a thin ring just behind the branch's first
      // (thick) one, at an angle, crossed it and the branch's rings up to the next fork went.
      if (walked >= skeleton[fork].radius) path.push_back(reached);
    }
    if (path.empty() && walked > 0.0) path.push_back(reached);  // the fork below is nearer
    // A branch that turns back over its parent by more than 120 degrees from the stub keeps the short
    // stub (straight back to the parent's next node, at most one radius): the tube drops such a turn
    // (see tube.h), and from a long stub it cut straight to the branch (a fin beside a limb of
    // AdTree's tree1).
    const Vector3d& at_fork = skeleton[fork].position;
    const Vector3d ahead = direction_along(skeleton, chain, skeleton[fork].radius);
    const Vector3d from_stub = path.empty() ? Vector3d::Zero() : Vector3d(at_fork - path.front());
    if (from_stub.dot(ahead) < -0.5 * from_stub.norm()) {
      const Vector3d back = skeleton[toward].position - at_fork;
      path.assign(1, at_fork + back.normalized() * std::min(back.norm(), skeleton[fork].radius));
      // That tube starts at the fork, or past it: where the fork lies less than the stub's radius
      // deep in the parent's mesh (a tube thinned by the repair, a skeleton that wanders in it), it
      // could meet the mesh nowhere, and the piece was written beside the tree (a 366-node limb of
      // the LPine1 plot's tree 4 that ran back alongside its parent from a fork 2 mm inside the
      // parent's tube). The stub then comes into the branch from the side or from behind, from
      // inside the mesh (see straight_stub), thinner if the mesh is thin there.
      if (depth && depth(at_fork) < radius)
        if (const auto from = straight_stub(skeleton, tree, fork, chain[1], ahead, radius, walked, depth, swept)) {
          path.assign(1, from->first);
          radius = from->second;
        }
    }
    // Whether the tube of radius r along a to b meets the mesh `depth` measures (its axis tested at
    // points half a radius apart).
    auto segment_meets = [&](const Vector3d& a, const Vector3d& b, double r) {
      const int steps = std::clamp(static_cast<int>(std::ceil((b - a).norm() / (0.5 * r))), 1, kMeetSamples);
      for (int i = 0; i <= steps; ++i)
        if (depth(a + (b - a) * (static_cast<double>(i) / steps)) > -r) return true;
      return false;
    };
    // The axis from the stub's end through the fork to the branch's first node, without the corners
    // the tube cuts across (kCutTurnCos). (A fork of seed 1's tree2_noise_1,
    // completed with --complete-all, lay 0.7 mm inside the mesh, its stub doubled back along a
    // parent that zigzagged outside it, and the branch turned back by 117 degrees: the axis met the
    // mesh at the fork only, the tube cut that corner, and the piece was written beside the tree.)
    auto meets = [&] {
      std::vector<Vector3d> axis(path.rbegin(), path.rend());
      axis.push_back(at_fork);
      std::vector<Vector3d> kept{axis.front()};
      const Vector3d& first = skeleton[chain[1]].position;
      for (std::size_t i = 1; i < axis.size(); ++i) {
        const Vector3d& next = i + 1 < axis.size() ? axis[i + 1] : first;
        const Vector3d in = axis[i] - kept.back(), out = next - axis[i];
        if (in.dot(out) >= kCutTurnCos * in.norm() * out.norm()) kept.push_back(axis[i]);
      }
      for (std::size_t i = 0; i + 1 < kept.size(); ++i)
        if (segment_meets(kept[i], kept[i + 1], radius)) return true;
      // To the branch's first node: from the fork at the branch's radius, as before; from the stub
      // across a cut corner at the stub's.
      if (segment_meets(kept.back(), first, kept.back() == at_fork ? skeleton[chain[1]].radius : radius)) return true;
      for (NodeId v : branch)
        if (v != chain[1] && segment_meets(skeleton[tree.parent[v]].position, skeleton[v].position, skeleton[v].radius))
          return true;
      return false;
    };
    // The parent's mesh may not reach the fork: its tube cuts across a turn of more than 120
    // degrees, and a join left out ends the parent's tube short of it. A piece whose tubes then meet
    // the mesh nowhere (no point of its axis, the stub's included, within its radius of it) was
    // written beside the tree (a limb of AdTree's Lille_2, at a hook whose tip the parent's tube
    // cut 5 cm short). Its stub follows the parent's path on, node by node, to the first node that
    // lies the stub's radius deep in the mesh (not past the fork below); if none within
    // `kStubNodes` does, it stays as it was. A piece that meets the mesh keeps its stub: from a
    // longer one, the tube of a branch that turns back cuts across the branch's first segment.
    const bool met = !depth || down || meets();  // the stub as it is
    if (!met && !path.empty()) {
      std::vector<Vector3d> longer;
      double thinner = radius;
      int nodes = 0;
      bool deep = false;
      for (NodeId at = fork, next = toward; on_branch(at, next) && nodes < kStubNodes; at = next, next = next_of(at), ++nodes) {
        const Vector3d& p = skeleton[next].position;
        thinner = std::min(thinner, 0.5 * skeleton[next].radius);
        if ((p - at_fork).norm() >= skeleton[fork].radius) longer.push_back(p);
        if (!longer.empty() && depth(longer.back()) >= thinner) {
          path = std::move(longer);
          radius = thinner;
          deep = true;
          break;
        }
      }
      // Failing that, the mesh the parent went into passes the fork by (the parent's tube thinned by
      // the repair, around a skeleton that wanders in it), and a piece that met it nowhere was
      // written beside the tree (a limb of the LPine1 plot's tree 4 at a fork of its stem 3.4 cm
      // outside the stem's thinned tube). The stub then goes straight from the fork to the nearest
      // point a stub's radius deep in the mesh, of a grid of points as near the fork as the stub
      // could follow the parent (four fork radii, not past the fork below).
      if (!deep && walked > 0.0) {
        double nearest = std::numeric_limits<double>::infinity();
        for_stub_grid(at_fork, walked, [&](const Vector3d& p, double distance) {
          if (distance < nearest && depth(p) >= radius) {
            nearest = distance;
            path.assign(1, p);
          }
        });
        // No point of it that deep (the LPine1 plot's tree 13: a fork 2.4 cm outside its parent's
        // thinned tube): a thinner stub from the deepest point around the fork (see straight_stub).
        if (!std::isfinite(nearest))
          if (const auto from = straight_stub(skeleton, tree, fork, chain[1], ahead, radius, walked, depth, swept)) {
            path.assign(1, from->first);
            radius = from->second;
          }
      }
    }
    // Still nowhere (a fork of seed 1's tree4_vdensity_3, completed, lay 1.5 cm outside the mesh: its
    // parent's chain, 0.0033 thick, was swept straight around a skeleton that wandered from it): the
    // stub goes straight from the fork through the nearest point of the mesh's surface to the stub's
    // radius inside.
    if (!met && nearest && !meets()) {
      const Vector3d on = nearest(at_fork);
      const Vector3d in = on - at_fork;
      if (in.norm() > 0.0) path.assign(1, Vector3d(on + in.normalized() * radius));
    }
    for (const Vector3d& position : path) {
      SkeletonNode node;
      node.position = position;
      node.radius = radius;
      const NodeId stub = add_node(piece, node);
      boost::add_edge(stub, piece.root, piece.graph);
      piece.root = stub;
    }
  }
  for (NodeId v : branch) {
    add(v, skeleton[v].radius);
    boost::add_edge(id[tree.parent[v]], id[v], piece.graph);
  }
  if (members) *members = std::move(branch);
  return piece;
}

Skeleton path_of(const Skeleton& sk, const std::vector<NodeId>& nodes) {
  Skeleton path;
  path.offset = sk.offset;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    SkeletonNode node;
    node.position = sk[nodes[i]].position;
    node.radius = sk[nodes[i]].radius;
    add_node(path, node);
    if (i > 0) boost::add_edge(i - 1, i, path.graph);
  }
  path.root = 0;
  return path;
}

std::vector<NodeId> forks_up_to(const Skeleton& skeleton, const ChainTree& tree, NodeId node, NodeId ancestor, double reach) {
  const auto& g = skeleton.graph;
  auto is_fork = [&](NodeId v) { return tree.children[v].size() >= 2; };
  // A tube's part (owned by its chain's first node): from the fork its chain ends at, if any, so
  // that the tube goes into the one join.
  NodeId start = node;
  if (!is_fork(node) && tree.chain_of[node] >= 0)
    if (const NodeId end = tree.chains[static_cast<std::size_t>(tree.chain_of[node])].nodes.back(); is_fork(end)) start = end;
  std::vector<NodeId> forks;
  if (is_fork(start)) forks.push_back(start);
  double along = 0.0;
  for (NodeId v = start; v != ancestor;) {
    const NodeId up = tree.parent[v];
    if (up == v) return {};  // the root, and no ancestor met
    along += (g[up].position - g[v].position).norm();
    if (along > reach) return {};
    v = up;
    if (is_fork(v)) forks.push_back(v);
  }
  return forks;
}

}  // namespace treeskel::modeling::detail
