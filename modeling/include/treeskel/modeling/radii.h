/// @file radii.h
/// Branch radii: measured on each node's points by a circle fit, then made consistent with the pipe
/// model (Leonardo da Vinci's rule: the cross section of a branch equals the sum of its children's).
#pragma once

#include "treeskel/complete.h"
#include "treeskel/modeling/straighten.h"
#include "treeskel/point_cloud.h"
#include "treeskel/prune.h"
#include "treeskel/skeleton.h"

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace treeskel::modeling {

/// A circle fitted to points in a plane.
struct CircleFit {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius = 0.0;    ///< 0 when the fit failed (fewer than 3 points, points on a line)
  double rms = 0.0;       ///< rms distance of the points to the circle
  double coverage = 0.0;  ///< angle covered by the points around the centre (radians)
};

/// Least-squares circle: the algebraic (Kåsa) fit refined by Gauss-Newton on the geometric distances.
CircleFit fit_circle(const std::vector<Eigen::Vector2d>& points);

/// One node's radius as its points measure it.
struct RadiusMeasurement {
  double radius = 0.0;  ///< fitted circle radius; 0 when the node was not measured
  double weight = 0.0;  ///< reliability in [0, 1]: 0 for unmeasured nodes, 1 for a well covered, clean circle
  double offset = 0.0;  ///< distance of the circle's centre from the node (at most `radius`)
};

/// The factor the skeleton of a model is pruned with (`PruneOptions::radius_factor`; `skeletonize`
/// keeps the skeleton's 1.75): a leaf branch is removed when it stays within one radius (plus half a
/// band) of the branch it leaves. The twigs between the two lie along their hosts and are spurs of
/// the level sets about as often as real short branches. A skeleton keeps its branch points precise
/// by removing them; a model needs their wood, without which up to 8% of a real cloud's points (the
/// pine's of TreeLS) lay farther than 2% of the tree's height from the mesh. The short ones are
/// stubs (`RadiusOptions::stub_length`), so the two were chosen together (docs/models.md).
inline constexpr double kModelPruneRadius = 1.0;

/// The shortest leaf branch of a model's skeleton, in band widths (`PruneOptions::min_bands`;
/// `skeletonize` keeps half a band). The twigs between half a band and one are found forks on sparse
/// scans, but in a model they add little wood and many crossings: AdTree's Paris_Luxembourg_1 took
/// 92 pieces into the union instead of 75 and 8.6 s instead of 5.2, for 0.001 more of its points
/// within 1% of its height (docs/models.md).
inline constexpr double kModelPruneBands = 1.0;

/// Sets `prune` to how a model's skeleton is pruned: `kModelPruneRadius` on the nodes' radii (not on
/// the points, `PruneOptions::point_host_factor` 0: the model's twigs and stubs were chosen with
/// it), `kModelPruneBands`, and no spurs removed at close forks (`PruneOptions::close_forks` 0: a
/// short twig beside a fork is wood the mesh shows, whether or not the fork is the level sets'
/// doubling of one).
inline void use_model_pruning(PruneOptions& prune) {
  prune.radius_factor = kModelPruneRadius;
  prune.point_host_factor = 0.0;
  prune.min_bands = kModelPruneBands;
  prune.close_forks = 0.0;
}

struct RadiusOptions {
  /// Leonardo exponent e: r_parent^e = sum of r_child^e at every fork. 2 is the pipe model (areas).
  double exponent = 2.0;
  /// A node needs this many points for a circle fit.
  std::size_t min_points = 8;
  /// A fit counts as reliable only if the rms distance of its points to the circle is at most this
  /// share of the radius ...
  double max_residual = 0.3;
  /// ... and its points cover at least this angle around the axis (radians).
  double min_coverage = 1.5;
  /// What a tip carries in the pipe model, in median twig lengths (the rest is branch length). Large
  /// values give every twig the same cross section (one pipe per tip); small ones make twigs taper
  /// to nothing. Chosen on the synthetic trees and pypetree (bench_radii).
  double tip_weight = 6.0;
  /// Share of a chain (from its start) whose reliable measurements set the chain's thickness.
  double start_share = 0.34;
  /// Nodes on each side of a node averaged when the taper along a chain is smoothed.
  int smoothing = 3;
  /// At a fork on the stem (from the root, at every fork the child that carries the most), a
  /// child's measured start may claim at most this many times the share of the fork's cross
  /// section that the pipe model gives it (what it carries over what all the children carry).
  /// Circle fits around a conifer's side branches take in the needles and come out as wide as the
  /// stem, and so do fits of small branches whose few points scatter; unbounded, such branches,
  /// carrying 0.3-5% of the length, took 15-50% of the stem at their forks: TreeLS's pine was
  /// modelled with a stem 0.4 times as thick as its points, LPine1's pines with none above half
  /// their height, plantscan3d's A3B4 with a stem that thinned to nothing by 3 m (docs/models.md).
  /// Bounded at every fork, not the stem's alone, the crowns of broadleaved trees grew thicker than
  /// their reference models. 0 leaves the shares unbounded. A saved skeleton's radii are bounded as
  /// fits are: those `skeletonize` writes are the level sets' mean distances, which take in needles
  /// as the fits do (TreeLS's pine from its saved skeleton: DBH 0.04 m unbounded, 0.19 m bounded).
  /// `treeskel model --stem-share-bound`.
  double max_share_over_pipe = 4.0;
  /// At every fork, each child gets at least this share of what the pipe model gives it (its
  /// carried length over what all the children carry), whatever the circle fits of its siblings
  /// say. A child the points do not measure is estimated by the tree's global scale, which the
  /// trunk sets; fits of a twig's few scattered points come out tens of times wider than that, and
  /// at each fork a measured sibling left an unmeasured one a hundredth of the cross section: four
  /// orders down AdTree's tree1 had twigs of 0.04 mm beside branches of 4 mm. 0: no floor; 1: the
  /// pipe model's shares wherever they are larger than the fits'.
  double min_share_of_pipe = 0.25;
  /// Along a branch that ends in a fork, the circle fits of the nodes within this many of their own
  /// radii of the fork are not used for its taper. There the level sets split: the node before the
  /// fork keeps part of its ring's points and its circle comes out small. Taken in, it pulled the
  /// branch's end down (radii never grow toward the tips), the fork shared the smaller cross section,
  /// and each order down started lower than its own fits, which could not raise it again: on seed 1's
  /// tree1_28189, a clean synthetic cloud, the second order was 0.86 of its true radius and the
  /// model 0.885 of the true volume (1.016 with the margin). 0: every fit counts.
  double fork_margin = 1.0;
  /// A tip shorter than this many radii of the branch it leaves (as a first fit gives them) is a
  /// stub: the radii are fitted again without it (its circle fits take in the points of the branch
  /// it sticks out of, and as a tip it cut that branch's taper in two), then it is hung back as a
  /// cylinder carrying its own length only in the pipe model (no tip allowance). The level sets of
  /// sparse or unevenly scanned trunks leave such spurs, and each took a twig's share of the trunk:
  /// on the synthetic trees thinned with height, seven spurs of 4-12 cm on a trunk 2.7 cm thick left
  /// it 0.67 of its true radius above them. 0: every tip is a twig. Only with a cloud. Chosen on the
  /// synthetic trees together with `kModelPruneRadius` and `fork_margin` (docs/models.md, "Stubs" and
  /// "A model prunes less than a skeleton").
  double stub_length = 6.5;
  /// After fitting, grow branches through the points that the fitted tubes leave more than a margin
  /// outside (`complete_skeleton`), then fit again: a model that reaches the parts of a crowded or
  /// sparse crown the skeleton passes by. The grafted twigs carry their own length only in the pipe
  /// model (no tip allowance, their circle fits unused), so they take almost nothing from the
  /// branches they hang from. Needs the cloud and `cell_size`.
  bool complete = false;
  CompleteOptions completion;  ///< its automatic (0) scales follow `cell_size`
  double cell_size = 0.0;      ///< the octree cell size the skeleton was extracted with
  /// Last, each limb's path is smoothed over a length of this many times its radius
  /// (`straighten_limbs`): thick limbs no longer zigzag where a sparse scan's level sets wandered,
  /// twigs keep their bends. 0: the skeleton's path as it is. Chosen on the real and synthetic
  /// clouds (docs/models.md, "Limbs as stiff as their thickness"). `treeskel model --stiffness`.
  double stiffness = 2.0;
};

/// Whether a circle fit is reliable enough to steer the radii: a radius, an rms residual within
/// `options.max_residual` of it and at least `options.min_coverage` covered.
bool is_reliable(const CircleFit& fit, const RadiusOptions& options);

/// What `fit_radii` did, for reports.
struct RadiusStats {
  std::size_t measured = 0;  ///< nodes with a circle fit
  std::size_t reliable = 0;  ///< of them, fits reliable enough to steer the radii
  bool used_stored = false;  ///< no cloud points: the skeleton's own radii were taken as measurements
  CompleteStats completion;  ///< what `complete` grafted (zeros when it did not run)
  std::size_t stubs = 0;         ///< tips found to be stubs (see `RadiusOptions::stub_length`)
  double base_lowered = 0.0;     ///< how far `reach_down` moved the root (0 without a cloud)
  StraightenStats straightened;  ///< what the limbs' smoothing moved (zeros when it did not run)
};

/// Least-squares circle fit of one node's points in the plane across its branch; see
/// measure_node_radii.
RadiusMeasurement measure_node_radius(const Skeleton& skeleton, const PointCloud& cloud, NodeId v,
                                      const RadiusOptions& options = {});

/// Least-squares circle fit of each node's points in the plane across its branch (algebraic fit,
/// refined by Gauss-Newton on the geometric distance). Fork nodes and nodes with fewer than
/// `options.min_points` points are not measured.
/// @param[in] skeleton  a tree whose nodes list their points in `cloud`
/// @return one measurement per node
std::vector<RadiusMeasurement> measure_node_radii(const Skeleton& skeleton, const PointCloud& cloud,
                                                  const RadiusOptions& options = {});

/// Replaces every node radius by one that obeys the pipe model:
/// - at every fork, r(fork)^e = sum over its children c of r(c)^e, exactly;
/// - along every path from the root, radii never increase;
/// - the shape follows the pipe model (cross section proportional to the branch length carried),
///   scaled per branch by the reliable measurements: measured values win where they are reliable,
///   the rule fills in twigs and occluded parts.
/// Without a cloud (`cloud == nullptr`, e.g. a skeleton read from a file) the skeleton's own radii
/// are the measurements. With a cloud, tips shorter than `options.stub_length` radii of the branch
/// they leave are stubs and the radii are fitted again without their share (see `RadiusOptions`).
/// With `options.complete` and a cloud, the skeleton gains the grafted
/// branches (see `RadiusOptions::complete`) and every radius is fitted again with them. Then, with a
/// cloud, the root goes down its trunk to where its points end (`reach_down`), and last each limb's
/// path is smoothed (`RadiusOptions::stiffness`, `straighten_limbs`): nodes move, radii stay.
/// @throws InputError when the skeleton is empty or not a tree, or nothing gives a positive radius.
/// @throws OptionError for an exponent outside [1, 4], `complete` with a cloud but no cell size, a
/// negative or non-finite `stub_length`, or a negative or non-finite `stiffness` (found by
/// `straighten_limbs`, once the radii are fitted).
void fit_radii(Skeleton& skeleton, const PointCloud* cloud, const RadiusOptions& options = {},
               RadiusStats* stats = nullptr);

}  // namespace treeskel::modeling
