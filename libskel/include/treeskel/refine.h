/// @file refine.h
/// Topology refinement at branch nodes (Fu et al. 2020, section IV.D, Algorithm 1). Branch nodes are
/// visited top-down by geodesic distance; the points of each are split by k-means into as many
/// clusters as the node has child branches (seeded by the points nearest to the children); a cluster
/// whose CPC centre lies farther from the node than τ = η·sqrt(Σ r_i²) (eq. 8, Leonardo's rule over the
/// children's radii) becomes a sibling node that takes over its child branch, and the node is
/// recentred on the points that remain.
#pragma once

#include "treeskel/cpc.h"
#include "treeskel/point_cloud.h"
#include "treeskel/skeleton.h"

namespace treeskel {

struct RefineOptions {
  double eta = 1.0;                    ///< η of eq. 8 (the paper's empirical value)
  int kmeans_iterations = 20;          ///< Lloyd iterations at most
  std::size_t min_cluster_points = 8;  ///< a smaller cluster is never split off
  CpcOptions cpc;                      ///< for the cluster centres and the recentred node
};

/// Refines the branch nodes in place. Returns the number of sibling nodes added.
std::size_t refine_topology(Skeleton& skeleton, const PointCloud& cloud, const RefineOptions& options = {});

}  // namespace treeskel
