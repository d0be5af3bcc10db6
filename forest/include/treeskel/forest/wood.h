/// @file wood.h
/// Wood and leaves told apart point by point, from the shape and the density of each point's 40
/// nearest: bark is a surface (its points scatter little off their plane) and a scan samples it at
/// least as densely as the foliage around it; a cluster of leaves or needles scatters in every
/// direction. The score is
///   0.25 planarity - scattering - 0.25 ln(d40 / median d40)
/// (eigenvalues l0 <= l1 <= l2 of the covariance of the 40 nearest: planarity (l1 - l0) / l2,
/// scattering l0 / l2; d40 the distance to the 40th, the median over the cloud), averaged over the
/// 20 nearest. A cloud in leaf (one in which that score calls 16% of the points leaves or more; in
/// proportion from 10%) also weighs the ways through each point: in the shortest-path tree of the
/// neighbour graph from the tree's base (its lowest point along `up`), the most points whose way to
/// the base passes through one of the point's 20 nearest, N, adds 0.1 log2(N / 45). Leaves hang at the
/// ends of the ways; the twigs among them carry the ways to everything beyond. A point is wood above
/// the threshold. Unsupervised and free of units: no training; the up axis counts only in a cloud
/// in leaf. Its limits are measured in docs/plots.md: on leafless trees it calls up to 10% of the
/// points leaves (thin twigs high in a crown look like leaves to the shape), and a fifth of arbor's
/// foliage and a sixth of the synthetic trees' stay in with the wood.
#pragma once

#include "treeskel/point_cloud.h"

#include <cstdint>
#include <vector>

namespace treeskel::forest {

struct WoodOptions {
  /// Wood above this score, chosen with the weights on arbor's labelled broadleaf tree, the synthetic
  /// plots and leafless real trees (docs/plots.md: how, and what it gives on each).
  double threshold = -0.4;
  /// Parts of the wood of this many points or more that the leaves cut off from the largest part are
  /// joined back to it (0: never): the points called leaves on the shortest way back become wood.
  std::size_t join_parts = 40;
  /// The axis the tree grows along: the base, where the ways through the wood start, is its lowest point.
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  /// In a cloud in leaf, the score gains ways_weight log2(N / ways_reference), N the most points whose
  /// shortest way to the base passes through one of a point's 20 nearest (0: never).
  double ways_weight = 0.1;
  double ways_reference = 45;
  /// How much a cloud is in leaf, from the share of its points the shape and density alone call
  /// leaves: not below ways_from_share, fully from ways_full_share, in proportion between.
  double ways_from_share = 0.10;
  double ways_full_share = 0.16;
};

struct WoodLeaf {
  std::vector<std::uint8_t> is_wood;  ///< per point: 1 for wood
  std::vector<float> score;           ///< per point: the smoothed score (above the threshold: wood)
  std::size_t wood_points = 0, leaf_points = 0;
  std::size_t joined = 0;  ///< points called leaves that became wood to join the wood's parts
  double in_leaf = 0;      ///< 0-1: how much the ways through the points were weighed (WoodOptions)
  double leaf_share() const;
};

/// Classifies every point of `cloud` as wood or leaf. A cloud of 40 points or fewer is all wood
/// (too few for the neighbourhoods). Deterministic, and the same for any number of threads.
WoodLeaf separate_wood(const PointCloud& cloud, const WoodOptions& options = {});

/// A single tree's cloud in which at least this share of the points look like leaves to
/// `estimate_leaf_share` is called leafy (docs/plots.md: the shares of the clouds we have).
constexpr double kLeafyShare = 0.16;

/// Where `estimate_leaf_share` looks. The rule depends on the density (a cluster of leaves thinned
/// out stops scattering), so a large cloud is not thinned but cropped at its own density: around
/// `sites` points taken evenly through the cloud's order, each site's `crop` nearest points (found
/// in a grid of cells); the `inner` nearest of them count, scored within the crop (their
/// neighbourhoods lie inside it).
struct LeafShareSample {
  std::size_t whole_up_to = 10000;  ///< a cloud of this many points or fewer is classified whole
  std::size_t sites = 100;
  std::size_t crop = 320;
  std::size_t inner = 50;
};

/// The share of `cloud`'s points the shape and density of `separate_wood`'s score call leaves (before
/// the ways through the points count and cut-off wood is joined back), estimated where the cloud is large: a counting sort of its points into cells and the rule on
/// sites x inner of them, 0.02-0.04 s up to 150k points and 0.05-0.07 s at 1-1.5 M. Deterministic, and
/// the same for any number of threads.
double estimate_leaf_share(const PointCloud& cloud, const LeafShareSample& sample = {});

/// The points of `cloud` whose `keep` is `value`, with their normals, colours and classes; same offset.
PointCloud select_points(const PointCloud& cloud, const std::vector<std::uint8_t>& keep, std::uint8_t value);

}  // namespace treeskel::forest
