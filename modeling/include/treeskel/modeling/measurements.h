/// @file measurements.h
/// What a forester measures on a tree model: height, trunk diameter at breast height (DBH), wood
/// volume and length, branches by order, and the cylinder table of quantitative structure models
/// (QSM: TreeQSM, SimpleForest).
#pragma once

#include "treeskel/point_cloud.h"
#include "treeskel/skeleton.h"

#include <Eigen/Core>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace treeskel::modeling {

struct MeasureOptions {
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  ///< the direction the tree grows along
  /// Height of the DBH above the base, in the cloud's units (1.3 for a cloud in metres).
  double breast_height = 1.3;
  /// With a cloud, the DBH is a circle fitted to the points of a slice across the trunk at breast
  /// height, as a forester's tape would measure it; the model's radius there (which the pipe model's
  /// taper smooths over the whole trunk) is the fallback when the slice gives no reliable circle.
  bool dbh_from_points = true;
};

/// Where a DBH comes from.
enum class DbhSource { none, points, model };

/// One row of the cylinder table: a skeleton edge as a cylinder of the same volume as its frustum.
struct QsmCylinder {
  std::size_t id = 0;       ///< 1-based
  std::size_t parent = 0;   ///< id of the cylinder below it; 0 for the first trunk cylinder
  std::size_t branch = 0;   ///< 1-based branch id; branch 1 is the trunk
  int order = 0;            ///< 0 for the trunk, 1 for the branches it carries, ...
  std::size_t position = 0; ///< 1-based position of the cylinder in its branch
  Eigen::Vector3d start = Eigen::Vector3d::Zero();  ///< world frame (offset added)
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  ///< unit
  double length = 0.0;
  double radius = 0.0;
};

struct TreeMeasurements {
  double height = 0.0;          ///< extent along `up` from the base to the highest point
  std::optional<double> dbh;    ///< trunk diameter at `breast_height` above the base; unset if shorter
  DbhSource dbh_source = DbhSource::none;
  double breast_height = 0.0;
  /// Height above the base where the DBH was taken: `breast_height`, or a little below it where the
  /// points show the stem swelling there (a fork, a branch, a burl), as foresters measure, or where no
  /// reliable circle fits at breast height (a fork there) and one fits just below.
  double dbh_height = 0.0;
  bool dbh_unfit_at_breast_height = false;  ///< taken below breast height because none fits there
  double volume = 0.0;          ///< sum of the frustums between adjacent skeleton nodes
  double length = 0.0;          ///< total skeleton length
  double trunk_length = 0.0;    ///< length of branch 1
  std::vector<std::size_t> branches_by_order;  ///< [k] = number of branches of order k
  std::vector<QsmCylinder> cylinders;
};

/// How the DBH was taken, for summaries: " (fitted to the points)", " (fitted to the points at 1.1,
/// below a swelling at 1.3)", " (fitted to the points at 1.1, where none fits at 1.3)", " (from the
/// model)", or "" without a DBH.
std::string dbh_note(const TreeMeasurements& m);

/// Measures a skeleton whose radii are fitted. Branches follow the thickest child at every fork
/// (the others start branches one order higher); the trunk, the thickest of the children that rise
/// at least half as far above the fork as the highest one. The DBH is fitted to the points of a
/// slice across the trunk at breast height, or of the slice below it where the stem swells there.
/// The base is the lowest point the skeleton stands for: the lowest of its points in `cloud` when
/// given, else its root.
/// @throws InputError when the skeleton is empty or not a tree.
TreeMeasurements measure_tree(const Skeleton& skeleton, const PointCloud* cloud, const MeasureOptions& options = {});

}  // namespace treeskel::modeling
