// The narrow interface between the MeshLab plugin and the treeskel library.
//
// MeshLab 2020.09 is built as C++14 and its headers do not compile as C++17, while the library is C++17.
// This header is the only one both sides include, so it is C++14 and holds plain numbers, flat arrays
// and strings: no Eigen, no Boost, no library type. bridge.cpp (C++17) implements it with the library;
// filter_treeskel.cpp (C++14) calls it with the points of a MeshLab layer.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace treeskel {
namespace meshlab {

/// Progress in percent and the stage's name: the signature of MeshLab's `vcg::CallBackPos`.
using ProgressFn = bool (*)(const int percent, const char* stage);

/// The skeleton method's options. Distances are in the cloud's units; a distance of 0 means "what the
/// library chooses for this cloud" (see `resolve_scales`).
struct SkeletonParams {
  double up[3] = {0.0, 0.0, 1.0};  ///< axis the tree grows along
  int octree_depth = 0;            ///< 0: chosen from the density
  double points_per_cell = 0.0;
  double band_width = 0.0;
  double prune_length = 0.0;
  double bridge_distance = 0.0;  ///< negative: never bridge gaps
  double cpc_weight = 0.0;
  double eta = 0.0;
  int samples = 0;
  double tension = 0.0;
  bool prune = true, cpc = true, refine = true, junctions = true, smooth = true;
  /// Set aside the points that look like leaves or needles first and make the skeleton of the wood
  /// (`--wood-only`); the leaves come back in the layer's `leaves`.
  bool wood_only = false;
};

/// The radii and mesh options.
struct ModelParams {
  double exponent = 0.0;
  double tip_weight = 0.0;
  bool complete = false;  ///< grow branches through the points the tubes pass by (`model --complete`)
  /// With `complete`: grow the tufts on the bark and the bushes too (`model --complete-all`).
  bool complete_all = false;
  int segments = 0;
  int min_segments = 0;
  double min_radius = 0.0;
  bool repair = true;
  bool allow_defects = false;
  double breast_height = 0.0;  ///< for the DBH in the log
};

/// The library's defaults (every scale 0, i.e. automatic).
SkeletonParams default_skeleton_params();
ModelParams default_model_params();

/// Replaces the automatic (0) scales of `params` with the values the library uses on the cloud `xyz`
/// (x0 y0 z0 x1 ...). The octree depth stays as it is: the library's cells can lie between two depths'
/// sizes (`OctreeOptions::depth_steps`), which a depth alone does not say, and the scales are those of
/// the cells depth 0 chooses. `for_mesh`: the scales of the mesh filter's skeleton, pruned as `treeskel
/// model` prunes (its shortest branch a whole band, not half). Returns false with `error` set when the
/// cloud cannot be used.
bool resolve_scales(const std::vector<double>& xyz, SkeletonParams& params, std::string& error, bool for_mesh = false);

/// What either filter hands back beside its layer: for MeshLab's log and a layer of leaves.
struct LayerNotes {
  std::string summary;  ///< one line for MeshLab's log
  std::string wood;     ///< with `wood_only`: how many points looked like wood and leaves, for the log
  std::vector<double> leaves;         ///< with `wood_only`: the points set aside (x0 y0 z0 ...)
  std::vector<std::string> warnings;  ///< for MeshLab's log, as `treeskel skeletonize` and `model` warn
};

/// A skeleton: node positions (x0 y0 z0 ...), one radius per node and edges as node index pairs.
struct SkeletonLayer : LayerNotes {
  std::vector<double> xyz;
  std::vector<double> radius;
  std::vector<int> edges;
};

/// A closed triangle mesh: vertex positions and vertex index triples, outward-facing.
struct MeshLayer : LayerNotes {
  std::vector<double> xyz;
  std::vector<int> triangles;
};

/// Skeleton of the cloud `xyz`, with radii fitted by the pipe model. Returns false with `error` set
/// (too few points, a flat cloud, a failure inside the library); never throws.
bool tree_skeleton(const std::vector<double>& xyz, const SkeletonParams& skeleton, const ModelParams& model,
                   ProgressFn progress, SkeletonLayer& out, std::string& error);

/// The watertight branch mesh of the cloud `xyz`. A mesh that fails its checks (closed, manifold, no
/// self-intersection) is an error unless `model.allow_defects`; one whose only fault is a swept-apart
/// limb lying beside the tree (several closed components) is kept, with a warning.
bool tree_mesh(const std::vector<double>& xyz, const SkeletonParams& skeleton, const ModelParams& model,
               ProgressFn progress, MeshLayer& out, std::string& error);

}  // namespace meshlab
}  // namespace treeskel
