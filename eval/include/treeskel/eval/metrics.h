/// @file metrics.h
/// The paper's measures of a skeleton against its ground truth (Fu et al. 2020, section V.A.2) and the
/// ones it lacks, without which spurious branches go unseen:
///   SPD (eq. 10-11)    mean distance from the ground truth's nodes to the nearest predicted edge;
///   reverse SPD        the same from the predicted nodes to the ground truth's edges;
///   BPC, EPC (eq. 15, 18)  share of ground-truth branch points (degree >= 3) / endpoints (degree 1)
///                      matched closer than τ by a minimum-cost bijection (Hungarian method);
///   their precision    matched / predicted branch points or endpoints;
///   cycles, components of the predicted graph.
#pragma once

#include "treeskel/skeleton.h"

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace treeskel::eval {

struct MetricOptions {
  double tau = 0.05;  ///< matching threshold τ (the paper's default, for clouds normalised to size 1)
};

struct Metrics {
  double spd = 0.0;
  double reverse_spd = 0.0;
  double bpc = 0.0, epc = 0.0;                    ///< recall (the paper's coverage)
  double bp_precision = 0.0, ep_precision = 0.0;  ///< matched / predicted
  std::size_t truth_branch_points = 0, predicted_branch_points = 0, matched_branch_points = 0;
  std::size_t truth_endpoints = 0, predicted_endpoints = 0, matched_endpoints = 0;
  std::size_t cycles = 0, components = 0;
};

/// All measures of `predicted` against `truth`, in their world frames (position + offset).
Metrics evaluate(const Skeleton& predicted, const Skeleton& truth, const MetricOptions& options = {});

/// Mean distance from the nodes of `from` to the nearest edge of `to` (or node, if `to` has no edge).
double skeleton_point_deviation(const Skeleton& from, const Skeleton& to);

/// Minimum-cost assignment (Hungarian method, O(n² m)). `cost` is n × m; every row is assigned a
/// distinct column when n <= m, every column a distinct row otherwise. Returns the column of each row,
/// or -1 for a row left unassigned.
std::vector<int> min_cost_assignment(const Eigen::MatrixXd& cost);

/// Matches `truth` points to `predicted` points by a minimum-cost bijection on their distances and
/// counts the pairs closer than `tau`.
std::size_t matched_within(const std::vector<Eigen::Vector3d>& truth, const std::vector<Eigen::Vector3d>& predicted,
                           double tau);

}  // namespace treeskel::eval
