#include "treeskel/modeling/straighten.h"

#include "treeskel/error.h"
#include "treeskel/modeling/chains.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <vector>

namespace treeskel::modeling {

namespace {

/// Nodes farther along the limb than this many spreads weigh nothing.
constexpr double kReach = 3.0;
/// A node counts as moved when it moved by more than this share of its radius.
constexpr double kMovedRadii = 0.01;
/// A fork stays where it is when its second-thickest child is at least this share of its thickest
/// child's radius: two limbs part there, and moving the fork would turn one of them onto the other.
/// A fork with thinner side branches moves with its limb (and its side branches with it).
constexpr double kHeldForkShare = 0.5;

/// The limbs of `t`: each a path of nodes whose first is the root or the fork it leaves (held where
/// it is) and whose last is a tip. Listed so that a limb's first node belongs to a limb listed before.
std::vector<std::vector<NodeId>> limbs_of(const Skeleton& skeleton, const ChainTree& t) {
  std::vector<std::vector<NodeId>> limbs;
  std::vector<std::size_t> limb_of_chain(t.chains.size(), 0);
  for (std::size_t id = 0; id < t.chains.size(); ++id) {
    const Chain& chain = t.chains[id];
    bool continues = false;
    if (chain.parent >= 0) {
      // The sibling that goes on with the parent's limb: the thickest at its first node (the
      // first listed of equals).
      const auto& siblings = t.chains[static_cast<std::size_t>(chain.parent)].children;
      std::size_t main = siblings.front();
      for (std::size_t s : siblings)
        if (skeleton[t.chains[s].nodes[1]].radius > skeleton[t.chains[main].nodes[1]].radius) main = s;
      continues = main == id;
    }
    if (continues) {
      const std::size_t limb = limb_of_chain[static_cast<std::size_t>(chain.parent)];
      limbs[limb].insert(limbs[limb].end(), chain.nodes.begin() + 1, chain.nodes.end());
      limb_of_chain[id] = limb;
    } else {
      limb_of_chain[id] = limbs.size();
      limbs.push_back(chain.nodes);
    }
  }
  return limbs;
}

/// Smooths the nodes strictly between `a` and `b` of `limb` (positions `at`, distances `along`) into
/// `placed`: each the Gaussian-weighted mean of the run a..b mirrored through both of its ends (an odd
/// reflection), with a spread of `factor` times the node's radius.
void smooth_run(const Skeleton& skeleton, const std::vector<NodeId>& limb, const std::vector<Eigen::Vector3d>& at,
                const std::vector<double>& along, std::size_t a, std::size_t b, double factor,
                std::vector<Eigen::Vector3d>& placed) {
  const auto lo = static_cast<std::ptrdiff_t>(a), hi = static_cast<std::ptrdiff_t>(b);
  // Index k in [2a - b, 2b - a]: a node of the run, or its reflection through a or through b.
  const auto sample = [&](std::ptrdiff_t k, double& s) -> Eigen::Vector3d {
    if (k < lo) {
      const auto j = static_cast<std::size_t>(2 * lo - k);
      s = 2.0 * along[a] - along[j];
      return 2.0 * at[a] - at[j];
    }
    if (k > hi) {
      const auto j = static_cast<std::size_t>(2 * hi - k);
      s = 2.0 * along[b] - along[j];
      return 2.0 * at[b] - at[j];
    }
    s = along[static_cast<std::size_t>(k)];
    return at[static_cast<std::size_t>(k)];
  };
  for (std::size_t i = a + 1; i < b; ++i) {
    const double spread = factor * skeleton[limb[i]].radius;
    if (!(spread > 0.0)) continue;
    const double reach = kReach * spread, inv = 1.0 / (2.0 * spread * spread);
    Eigen::Vector3d sum = at[i];
    double weight = 1.0;
    for (const std::ptrdiff_t step : {-1, 1})
      for (auto k = static_cast<std::ptrdiff_t>(i) + step; k >= 2 * lo - hi && k <= 2 * hi - lo; k += step) {
        double s = 0.0;
        const Eigen::Vector3d p = sample(k, s);
        const double d = s - along[i];
        if (std::abs(d) > reach) break;
        const double w = std::exp(-d * d * inv);
        sum += w * p;
        weight += w;
      }
    placed[i] = sum / weight;
  }
}

}  // namespace

StraightenStats straighten_limbs(Skeleton& skeleton, double factor) {
  if (!(factor >= 0.0) || !std::isfinite(factor)) throw OptionError("the limbs' stiffness factor must be 0 or positive");
  StraightenStats stats;
  if (factor == 0.0) return stats;
  const ChainTree t = build_chains(skeleton);
  const auto limbs = limbs_of(skeleton, t);
  stats.limbs = limbs.size();
  const std::size_t n = skeleton.node_count();
  // Forks where two limbs part are held (see kHeldForkShare).
  std::vector<char> held(n, 0);
  for (NodeId v = 0; v < n; ++v) {
    const auto& kids = t.children[v];
    if (kids.size() < 2) continue;
    double first = 0.0, second = 0.0;
    for (NodeId c : kids) {
      const double r = skeleton[c].radius;
      if (r > first) {
        second = first;
        first = r;
      } else if (r > second) {
        second = r;
      }
    }
    held[v] = second >= kHeldForkShare * first ? 1 : 0;
  }
  std::vector<Eigen::Vector3d> original(n);
  for (NodeId v = 0; v < n; ++v) original[v] = skeleton[v].position;
  // What each node's own limb's smoothing moved it, beside following its fork.
  std::vector<double> own_shift(n, 0.0);
  std::vector<double> along;
  std::vector<Eigen::Vector3d> at, placed;
  for (const auto& limb : limbs) {
    const std::size_t m = limb.size() - 1;  // the last index (a tip); limb[0] was placed by its own limb
    at.resize(m + 1);
    for (std::size_t i = 0; i <= m; ++i) at[i] = skeleton[limb[i]].position;
    // Distances along the limb as the skeleton had it (its first node may have moved already).
    along.assign(m + 1, 0.0);
    for (std::size_t i = 1; i <= m; ++i) along[i] = along[i - 1] + (original[limb[i]] - original[limb[i - 1]]).norm();
    // A side limb follows its fork where the fork moved, the more the nearer, over the spread of the
    // fork's own limb (a short twig moves whole, tip and all, and keeps its shape).
    const Eigen::Vector3d moved = at[0] - original[limb[0]];
    const double fork_spread = factor * skeleton[limb[0]].radius;
    if (moved.squaredNorm() > 0.0 && fork_spread > 0.0)
      for (std::size_t i = 1; i <= m && along[i] <= kReach * fork_spread; ++i)
        at[i] += moved * std::exp(-along[i] * along[i] / (2.0 * fork_spread * fork_spread));
    // Each run between held nodes (the limb's start, the forks where limbs part, the tip) on its own.
    placed = at;
    for (std::size_t a = 0; a < m;) {
      std::size_t b = a + 1;
      while (b < m && !held[limb[b]]) ++b;
      smooth_run(skeleton, limb, at, along, a, b, factor, placed);
      a = b;
    }
    for (std::size_t i = 1; i <= m; ++i) {
      own_shift[limb[i]] = (placed[i] - at[i]).norm();
      skeleton[limb[i]].position = placed[i];
    }
  }
  for (NodeId v = 0; v < n; ++v) {
    const double shift = (skeleton[v].position - original[v]).norm();
    const double radius = skeleton[v].radius;
    if (shift > kMovedRadii * radius) ++stats.moved;
    stats.largest_shift = std::max(stats.largest_shift, shift);
    if (radius > 0.0) stats.largest_shift_radii = std::max(stats.largest_shift_radii, own_shift[v] / radius);
  }
  return stats;
}

}  // namespace treeskel::modeling
