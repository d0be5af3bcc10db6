#include "model_warnings.h"

#include "treeskel/forest/wood.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace treeskel::cli {

namespace {

/// Below this share of the skeleton's length inside the mesh, the summary warns.
constexpr double kCoverageWarning = 0.95;
/// Below this share of the wood the fitted radii describe (their frustums, whose volume the summary
/// reports) inside the mesh, the summary warns: the model is much thinner than the measurements.
/// The fourteen real clouds of docs/models.md give 0.80-0.96 (the spruce's trunk, narrowed at its
/// whorls, the 0.80); frustums that overlap do not lower the share.
constexpr double kWoodWarning = 0.85;
/// Sanity warnings: a tree this many times wider than tall, taller than this (the tallest known
/// trees are about 116 m), a DBH over this (the widest trunks are about 11 m across, but a DBH over
/// 3 m is rare enough to check).
constexpr double kUpAxisRatio = 1.5;
constexpr double kTallestTree = 150.0;
constexpr double kWidestTrunk = 3.0;
/// At least this share of the cloud in parts beyond the bridging distance, left out: several trees?
constexpr double kFarPartsWarning = 0.1;


/// What looks wrong about the input, from the skeleton's extent and the measurements: an up axis
/// along which the tree is much shorter than across, units that are not metres, a trunk no real
/// tree has.
std::vector<std::string> sanity_warnings(const Skeleton& skeleton, const Eigen::Vector3d& up,
                                         const modeling::TreeMeasurements& m, double breast_height) {
  std::vector<std::string> out;
  Eigen::AlignedBox3d box;
  for (NodeId v = 0; v < skeleton.node_count(); ++v) box.extend(skeleton[v].position);
  if (box.isEmpty()) return out;
  const Eigen::Vector3d size = box.sizes();
  const Eigen::Vector3d u = up.normalized();
  double along = 0.0, across = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double share = std::abs(u[a]);
    along += share * size[a];
    across = std::max(across, (1.0 - share) * size[a]);
  }
  if (across > kUpAxisRatio * along) {
    std::ostringstream w;
    w << "the tree is " << across / along << " times wider than tall along the up axis: if it grows along another "
      << "axis, say so with --up (e.g. --up y)";
    out.push_back(w.str());
  }
  if (m.height > kTallestTree) {
    std::ostringstream w;
    w << "the tree is " << m.height << " units tall: if the units are centimetres or millimetres, the breast height ("
      << breast_height << ") and every default in metres are wrong; convert the cloud or set --breast-height";
    out.push_back(w.str());
  }
  if (m.dbh && *m.dbh > kWidestTrunk) {
    std::ostringstream w;
    w << "a DBH of " << *m.dbh << " is over " << kWidestTrunk << ", rare in any tree: check the units, the up axis, "
      << "or whether this is a tree (an airborne scan of a crown has no trunk to measure)";
    out.push_back(w.str());
  }
  if (!m.dbh && m.height > 0.0 && m.height < breast_height)
    out.push_back("the tree is shorter than breast height, so it has no DBH");
  // Parts of the cloud too far from the tree to be bridged: another tree beside it (a plot, a
  // street), or a tree that occlusion cut in pieces. Only the largest part is modelled.
  std::size_t in_tree = 0;
  for (NodeId v = 0; v < skeleton.node_count(); ++v) in_tree += skeleton[v].points.size();
  const std::size_t all = in_tree + skeleton.left_out.total();
  const std::size_t far = skeleton.left_out.far_parts;
  if (all > 0 && static_cast<double>(far) >= kFarPartsWarning * static_cast<double>(all)) {
    std::ostringstream w;
    w << far << " of the cloud's " << all << " points (" << std::lround(100.0 * static_cast<double>(far) / static_cast<double>(all))
      << "%) lie in parts too far from the tree to be joined to it and are left out of the model: the cloud may hold "
      << "several trees (a plot, a street) or a tree that occlusion cut in pieces; 'treeskel plot' models each tree of a plot, or join "
      << "the parts with a longer --bridge";
    out.push_back(w.str());
  }
  return out;
}

}  // namespace

modeling::MeshCheck check_swept(const modeling::TreeMesh& mesh, const modeling::SweepStats& stats, bool repaired) {
  modeling::MeshCheck check = modeling::check_mesh(mesh, false);
  check.self_intersections = stats.self_intersections;
  check.self_intersections_checked = repaired;
  return check;
}

bool only_apart(const modeling::MeshCheck& check) {
  modeling::MeshCheck as_one = check;
  as_one.components = 1;
  return !check.ok() && as_one.ok();
}

namespace {

/// Collects sentences, each written from its parts.
class Sentences {
 public:
  template <class... Parts>
  void operator()(const Parts&... parts) {
    std::ostringstream w;
    (w << ... << parts);
    list.push_back(w.str());
  }
  std::vector<std::string> list;
};

}  // namespace

std::vector<std::string> mesh_warnings(const modeling::MeshCheck& check, const modeling::SweepStats& sweep,
                                       const modeling::SkeletonCoverage& coverage, bool unite_apart) {
  Sentences warn;
  if (only_apart(check))
    warn("the mesh has ", check.components, " closed components: ", check.components - 1,
         " swept-apart limb(s) do not touch the rest; written as they are");
  if (sweep.pieces_failed > 0)
    warn(sweep.pieces_failed, " limb(s)",
         unite_apart ? " could not be united with the tree without the mesh crossing itself (or past the union's budget)"
                     : " found no room at their forks (--no-unite)",
         " and are left out");
  if (sweep.float_crossings > 0)
    warn("rounded to 32-bit floats in the input's frame (as PLY, STL and MeshLab hold it), the mesh crosses itself at ",
         sweep.float_crossings, " face pairs (OBJ keeps full precision; --local writes local coordinates)");
  if (coverage.share() < kCoverageWarning)
    warn("the mesh holds only ", std::lround(100.0 * coverage.share()), "% of the skeleton's length (",
         coverage.inside_length, " of ", coverage.length, ")");
  const modeling::WoodInside& wood = coverage.wood;
  if (wood.share() < kWoodWarning)
    warn("the mesh holds ", std::lround(100.0 * wood.share()), "% of the wood the fitted radii describe (",
         wood.inside, " of ", wood.samples, " points drawn in their frustums, of volume ", wood.volume,
         "): the sweep thinned ", sweep.joins_thinned, " join(s) and ", sweep.repaired_shrunk,
         " branch(es) with what they carry to keep the mesh from crossing itself, and narrows the necks of forks");
  return std::move(warn.list);
}

std::vector<std::string> model_warnings(const ModelOutcome& o) {
  Sentences warn;
  warn.list = mesh_warnings(o.check, o.sweep, o.coverage, o.unite_apart);
  for (auto& w : sanity_warnings(o.skeleton, o.up, o.measurements, o.breast_height)) warn.list.push_back(std::move(w));
  return std::move(warn.list);
}

std::string leafy_warning(const PointCloud& cloud, const std::string& remedy) {
  const double share = forest::estimate_leaf_share(cloud);
  if (share < forest::kLeafyShare) return {};
  std::ostringstream w;
  w << "the cloud looks leafy: about " << std::lround(100.0 * share)
    << "% of its points look like leaves or needles, which the skeleton follows as if they were twigs; "
    << remedy << " sets them aside, though it may also lose a crown's thinnest top (docs/plots.md)";
  return w.str();
}

std::string ground_note(std::size_t points, const std::string& option) {
  return "set aside " + std::to_string(points) +
         " points of ground and what lies on it around the stem's foot (" + option + ")";
}

std::string bushes_left_out(const CompleteStats& grafted, std::size_t points, const std::string& option,
                            const std::string& wood_only) {
  if (!grafted.leafy_bushes) return {};
  return option + ": " + std::to_string(grafted.bushy_points) + " of the " + std::to_string(points) +
         " points lie in bushes (leaves or needles, more than the share it grows twigs through): the bushes were "
         "left out, only the branches the tubes passed by were grown; " + wood_only + " sets the leaves aside";
}

std::string wood_split(std::size_t wood_points, std::size_t leaf_points, double in_leaf) {
  const std::size_t all = wood_points + leaf_points;
  std::ostringstream line;
  line << wood_points << " of " << all << " points look like wood; " << leaf_points << " (" << std::fixed
       << std::setprecision(1) << (all ? 100.0 * static_cast<double>(leaf_points) / static_cast<double>(all) : 0.0)
       << "%) look like leaves and are set aside";
  if (in_leaf >= 1.0) line << " (a cloud in leaf: the ways from its base through the points counted)";
  else if (in_leaf > 0.0) line << " (partly in leaf: the ways from its base through the points counted at " << std::setprecision(2) << in_leaf << " of their weight)";
  return line.str();
}

}  // namespace treeskel::cli
