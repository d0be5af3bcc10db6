// What a model's user should be told about it, the same from every front end: the command's stderr
// and report, `batch`'s summary, MeshLab's log. Apart from the options so that the MeshLab plugin
// can take it without the command line's dependencies.
#pragma once

#include "treeskel/complete.h"
#include "treeskel/modeling/coverage.h"
#include "treeskel/modeling/measurements.h"
#include "treeskel/modeling/sweep.h"
#include "treeskel/modeling/tree_mesh.h"
#include "treeskel/point_cloud.h"
#include "treeskel/skeleton.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace treeskel::cli {

/// A mesh whose only fault is several components, each closed (a limb swept apart that its union
/// did not reach): written with a warning, since leaving the limbs out would lose them.
bool only_apart(const modeling::MeshCheck& check);

/// A swept mesh's check as every front end makes it: modeling::check_mesh without its whole-mesh
/// self-intersection test, whose place the sweep's own test takes (made when `repaired`, the sweep's
/// `repair` option, is set; otherwise the check says it was not made).
modeling::MeshCheck check_swept(const modeling::TreeMesh& mesh, const modeling::SweepStats& stats, bool repaired);

/// What a model is made of, for `model_warnings`.
struct ModelOutcome {
  const Skeleton& skeleton;
  Eigen::Vector3d up;
  const modeling::TreeMeasurements& measurements;
  double breast_height;
  const modeling::MeshCheck& check;
  const modeling::SweepStats& sweep;
  const modeling::SkeletonCoverage& coverage;
  bool unite_apart;
};

/// What the user of a mesh alone should be told (model_warnings' first sentences): limbs apart or
/// left out, a mesh that crosses itself once in floats, less than 95% of the skeleton's length or 85%
/// of the wood its radii describe in the mesh.
std::vector<std::string> mesh_warnings(const modeling::MeshCheck& check, const modeling::SweepStats& sweep,
                                       const modeling::SkeletonCoverage& coverage, bool unite_apart);

/// What the user of a model should be told, one sentence each (without the input's name): limbs
/// apart or left out, a mesh that crosses itself once in floats, less than 95% of the skeleton or
/// 85% of its wood in the mesh, an up axis or units that look wrong, a DBH no tree has, a
/// tenth of the cloud or more left out in parts too far to join (several trees?).
/// Every front end (the command's stderr and report, MeshLab's log) says the same.
std::vector<std::string> model_warnings(const ModelOutcome& outcome);

/// Before any skeleton of a cloud not cleared of its leaves: when forest::estimate_leaf_share calls
/// it leafy, the warning (without the input's name), naming `remedy`, the front end's way to set
/// the leaves aside; empty otherwise.
std::string leafy_warning(const PointCloud& cloud, const std::string& remedy = "--wood-only");

/// Fewest points that look like wood a skeleton is made of; fewer is an error that names the option.
inline constexpr std::size_t kFewestWoodPoints = 10;

/// How the wood rule split a cloud, for the log or stderr after the option's name: "W of N points
/// look like wood; L (x%) look like leaves and are set aside", and when `in_leaf` (forest::WoodLeaf)
/// is above 0, that the ways through the points counted and how much.
std::string wood_split(std::size_t wood_points, std::size_t leaf_points, double in_leaf = 0.0);

/// The note for `points` points of ground set aside (no input name), naming `option`, the front
/// end's way that asked for it.
std::string ground_note(std::size_t points, const std::string& option);

/// When the completion that grows the bushes too (`--complete-all`, named `option`) left them out
/// because they hold more than `CompleteOptions::max_bush_share` of the `points` points (the crown is
/// leafy or needled), the warning (no input name), naming `wood_only`, the front end's way to set the
/// leaves aside; empty otherwise.
std::string bushes_left_out(const CompleteStats& grafted, std::size_t points, const std::string& option = "--complete-all",
                            const std::string& wood_only = "--wood-only");

}  // namespace treeskel::cli
