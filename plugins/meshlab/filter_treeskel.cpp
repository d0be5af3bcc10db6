#include "filter_treeskel.h"

#include "bridge.h"

#include <vcg/complex/allocate.h>

#include <algorithm>
#include <string>
#include <vector>

namespace bridge = treeskel::meshlab;

namespace {

const QStringList up_axes = {"+Z", "+Y", "+X", "-Z", "-Y", "-X"};
/// "Grow through missed points": `treeskel model` without completion, `--complete`, `--complete-all`.
const QStringList completions = {"no", "branches", "every group"};

/// The positions of the layer's live vertices, as doubles.
std::vector<double> points_of(const CMeshO& cloud) {
  std::vector<double> xyz;
  xyz.reserve(3 * static_cast<std::size_t>(cloud.vn));
  for (const auto& v : cloud.vert) {
    if (v.IsD()) continue;
    for (int a = 0; a < 3; ++a) xyz.push_back(static_cast<double>(v.cP()[a]));
  }
  return xyz;
}

/// A distance parameter shown in the cloud's units; its slider spans [0, max(limit, 2 value)].
RichAbsPerc distance(const char* name, double value, double limit, const char* label, const char* help) {
  const float top = static_cast<float>(std::max(limit, 2.0 * value));
  return RichAbsPerc(name, static_cast<float>(value), 0.0f, top > 0.0f ? top : 1.0f, label, help);
}

/// The method's parameters, with the library's defaults resolved for `cloud` when it can be used (so the
/// dialog shows real distances); a 0 distance or depth means "automatic", which is what the bundled
/// scripts hold so that they suit any cloud.
void add_skeleton_parameters(const CMeshO& cloud, RichParameterList& list, bool for_mesh) {
  bridge::SkeletonParams p = bridge::default_skeleton_params();
  std::string ignored;  // a cloud the method cannot use keeps the automatic zeros; applying it reports why
  if (cloud.vn > 0) bridge::resolve_scales(points_of(cloud), p, ignored, for_mesh);
  const double diagonal = cloud.vn > 0 ? static_cast<double>(cloud.bbox.Diag()) : 1.0;

  list.addParam(RichEnum("upAxis", 0, up_axes, "Up axis",
                         "Axis the tree grows along; the trunk base is the lowest part of the cloud along it."));
  list.addParam(RichInt("octreeDepth", p.octree_depth, "Octree depth",
                        "Subdivision depth of the octree whose cells' L1-medians are the skeleton points. "
                        "0: the deepest at which a typical cell holds 'Points per cell' points."));
  list.addParam(RichFloat("pointsPerCell", static_cast<float>(p.points_per_cell), "Points per cell",
                          "With octree depth 0, the typical number of points per cell that sets the depth."));
  list.addParam(distance("bandWidth", p.band_width, diagonal / 5, "Level set band width",
                         "Width of a band of geodesic distance from the root; sets the spacing of skeleton "
                         "nodes. 0: two octree cells."));
  list.addParam(distance("pruneLength", p.prune_length, diagonal / 5, "Shortest branch kept",
                         "Leaf branches shorter than this are removed as noise. 0: half a band width for the skeleton, a whole one for the mesh."));
  list.addParam(RichBool("bridgeGaps", true, "Bridge occlusion gaps",
                         "Join parts of the cloud separated by small gaps (occlusion) into one tree."));
  list.addParam(distance("bridgeDistance", p.bridge_distance, diagonal / 5, "Longest gap bridged",
                         "Gaps up to this long are bridged. 0: four octree cells."));
  list.addParam(RichFloat("cpcWeight", static_cast<float>(p.cpc_weight), "CPC weight",
                          "Weight of the cylindrical prior (equal distance to the surface) when recentring nodes."));
  list.addParam(RichFloat("eta", static_cast<float>(p.eta), "Refinement threshold (eta)",
                          "Factor of the radius-based topology refinement test at branch points."));
  list.addParam(RichInt("splineSamples", p.samples, "Spline samples per edge",
                        "Points inserted between adjacent nodes by the smoothing spline."));
  list.addParam(RichFloat("splineTension", static_cast<float>(p.tension), "Spline tension",
                          "Cardinal spline tension: 0 is Catmull-Rom, 1 straight segments."));
  list.addParam(RichBool("prune", p.prune, "Prune short branches", "Remove spurious short leaf branches."));
  list.addParam(RichBool("cpc", p.cpc, "Cylindrical prior (CPC)", "Recentre nodes on the branch axis."));
  list.addParam(RichBool("refine", p.refine, "Refine topology", "Split wrongly merged branches at branch points."));
  list.addParam(RichBool("junctions", p.junctions, "Place forks", "Move forks to where the branch axes meet."));
  list.addParam(RichBool("smooth", p.smooth, "Smooth", "Smooth the branches with a cardinal spline."));
  list.addParam(RichBool("woodOnly", p.wood_only, "Wood only",
                         "First set aside the points that look like leaves or needles (thin, flat or scattered "
                         "rather than lying on a cylinder) and make the skeleton of the wood; the points set aside "
                         "are added as a layer of their own. For trees in leaf: the leaves would otherwise be "
                         "followed as twigs. It may also set aside a crown's thinnest top."));
}

void add_radius_parameters(RichParameterList& list) {
  const bridge::ModelParams p = bridge::default_model_params();
  list.addParam(RichFloat("exponent", static_cast<float>(p.exponent), "Leonardo exponent",
                          "At every fork r(parent)^e = sum of r(child)^e; 2 keeps the cross-section area."));
  list.addParam(RichFloat("tipWeight", static_cast<float>(p.tip_weight), "Tip weight",
                          "How much each branch tip counts, in typical twig lengths, when the pipe model shares "
                          "a fork's cross-section among its children."));
  list.addParam(RichEnum("complete", p.complete ? (p.complete_all ? 2 : 1) : 0, completions, "Grow through missed points",
                         "no: the skeleton's branches only. branches: grow branches through the points that lie more "
                         "than an octree cell outside the fitted branches (crowded or sparsely scanned crowns), then "
                         "fit the radii again; tufts of noise on the bark and bushes of leaves are not grown; up to 3 "
                         "times slower. every group: the tufts and bushes too, as AdTree's models show them, unless "
                         "bushes hold more than a fifth of the points (a crown in leaf or needles: they are left out "
                         "and the log says so); up to 6 times slower."));
}

void add_mesh_parameters(const CMeshO& cloud, RichParameterList& list) {
  const bridge::ModelParams p = bridge::default_model_params();
  const double diagonal = cloud.vn > 0 ? static_cast<double>(cloud.bbox.Diag()) : 1.0;
  list.addParam(RichInt("segments", p.segments, "Sides around the trunk",
                        "Polygon sides around the thickest branch; thinner branches get fewer."));
  list.addParam(RichInt("minSegments", p.min_segments, "Fewest sides", "Fewest polygon sides around any branch."));
  list.addParam(distance("minRadius", p.min_radius, diagonal / 50, "Thinnest branch kept",
                         "Branches thinner than this radius are left out of the mesh. 0 keeps all."));
  list.addParam(RichFloat("breastHeight", static_cast<float>(p.breast_height), "Breast height",
                          "Height above the base at which the trunk diameter (DBH) is logged, in the cloud's units."));
  list.addParam(RichBool("repair", p.repair, "Remove self-intersections",
                         "Test the mesh for self-intersections and thin or leave out the branches that cross."));
  list.addParam(RichBool("keepDefective", p.allow_defects, "Keep a defective mesh",
                         "Add the mesh even if it fails its checks (not closed, not manifold, self-intersecting)."));
}

bridge::SkeletonParams skeleton_parameters(const RichParameterList& list) {
  bridge::SkeletonParams p = bridge::default_skeleton_params();
  const int axis = list.getEnum("upAxis");
  for (double& c : p.up) c = 0.0;
  p.up[2 - axis % 3] = axis < 3 ? 1.0 : -1.0;  // +Z +Y +X -Z -Y -X
  p.octree_depth = list.getInt("octreeDepth");
  p.points_per_cell = list.getFloat("pointsPerCell");
  p.band_width = list.getAbsPerc("bandWidth");
  p.prune_length = list.getAbsPerc("pruneLength");
  p.bridge_distance = list.getBool("bridgeGaps") ? list.getAbsPerc("bridgeDistance") : -1.0;
  p.cpc_weight = list.getFloat("cpcWeight");
  p.eta = list.getFloat("eta");
  p.samples = list.getInt("splineSamples");
  p.tension = list.getFloat("splineTension");
  p.prune = list.getBool("prune");
  p.cpc = list.getBool("cpc");
  p.refine = list.getBool("refine");
  p.junctions = list.getBool("junctions");
  p.smooth = list.getBool("smooth");
  p.wood_only = list.getBool("woodOnly");
  return p;
}

bridge::ModelParams model_parameters(const RichParameterList& list, bool mesh) {
  bridge::ModelParams p = bridge::default_model_params();
  p.exponent = list.getFloat("exponent");
  p.tip_weight = list.getFloat("tipWeight");
  // Scripts saved before "Grow through missed points" was a choice of three hold it as a RichBool,
  // whose true was "branches" (read as an enum, MeshLab's build asserts and the server aborts).
  const Value& grow = list.getParameterByName("complete").value();
  const int completion = grow.isBool() ? (grow.getBool() ? 1 : 0) : grow.getEnum();
  p.complete = completion > 0;
  p.complete_all = completion >= 2;
  if (mesh) {
    p.segments = list.getInt("segments");
    p.min_segments = list.getInt("minSegments");
    p.min_radius = list.getAbsPerc("minRadius");
    p.breast_height = list.getFloat("breastHeight");
    p.repair = list.getBool("repair");
    p.allow_defects = list.getBool("keepDefective");
  }
  return p;
}

CMeshO::VertexIterator add_vertices(CMeshO& mesh, const std::vector<double>& xyz) {
  const std::size_t n = xyz.size() / 3;
  auto first = vcg::tri::Allocator<CMeshO>::AddVertices(mesh, n);
  auto v = first;
  for (std::size_t i = 0; i < n; ++i, ++v)
    v->P() = Point3m(static_cast<Scalarm>(xyz[3 * i]), static_cast<Scalarm>(xyz[3 * i + 1]),
                     static_cast<Scalarm>(xyz[3 * i + 2]));
  return first;
}

}  // namespace

FilterTreeskelPlugin::FilterTreeskelPlugin() {
  typeList << FP_TREE_SKELETON << FP_TREE_MESH;
  for (FilterIDType id : types()) actionList << new QAction(filterName(id), this);
}

QString FilterTreeskelPlugin::pluginName() const { return "FilterTreeskel"; }

QString FilterTreeskelPlugin::filterName(FilterIDType filter) const {
  switch (filter) {
    case FP_TREE_SKELETON: return "Tree Skeleton (CPC)";
    case FP_TREE_MESH: return "Tree Mesh from Point Cloud";
    default: return QString();
  }
}

QString FilterTreeskelPlugin::filterInfo(FilterIDType filter) const {
  switch (filter) {
    case FP_TREE_SKELETON:
      return "The curve skeleton of a tree's raw point cloud (treeskel; Fu et al., IEEE Access 2020) as a layer "
             "of nodes joined by edges, each node's quality its fitted branch radius (Leonardo's rule). "
             "Distances in the cloud's units; 0 means automatic.";
    case FP_TREE_MESH:
      // Short: the dialog holds 26 parameters and must fit a screen 1024 pixels high.
      return "A closed, manifold mesh of a tree's trunk and branches from its point cloud (treeskel); "
             "height, DBH and volume in the log. Distances in the cloud's units, 0: automatic.";
    default: return QString();
  }
}

MeshFilterInterface::FilterClass FilterTreeskelPlugin::getClass(QAction* action) {
  return ID(action) == FP_TREE_MESH ? FilterClass(PointSet | Remeshing) : PointSet;
}

MeshFilterInterface::FILTER_ARITY FilterTreeskelPlugin::filterArity(QAction*) const { return SINGLE_MESH; }

int FilterTreeskelPlugin::getPreConditions(QAction*) const { return MeshModel::MM_NONE; }

int FilterTreeskelPlugin::getRequirements(QAction*) { return MeshModel::MM_NONE; }

int FilterTreeskelPlugin::postCondition(QAction*) const { return MeshModel::MM_NONE; }

void FilterTreeskelPlugin::initParameterSet(QAction* action, MeshModel& model, RichParameterList& list) {
  add_skeleton_parameters(model.cm, list, ID(action) == FP_TREE_MESH);
  add_radius_parameters(list);
  if (ID(action) == FP_TREE_MESH) add_mesh_parameters(model.cm, list);
}

bool FilterTreeskelPlugin::applyFilter(QAction* action, MeshDocument& document, const RichParameterList& list,
                                       vcg::CallBackPos* progress) {
  const bool mesh = ID(action) == FP_TREE_MESH;
  MeshModel* source = document.mm();
  if (source == nullptr) {
    return fail("No layer is selected: load a tree point cloud first.");
  }
  const std::vector<double> xyz = points_of(source->cm);
  const bridge::SkeletonParams sp = skeleton_parameters(list);
  const bridge::ModelParams mp = model_parameters(list, mesh);
  std::string error;
  // With "Wood only": the points set aside, as a layer of their own beside the source (the new
  // skeleton or mesh stays the current layer), and the split in the log.
  const QString label = source->label();
  auto add_leaves = [&](const bridge::LayerNotes& notes) {
    if (notes.wood.empty()) return;
    Log("%s (layer '%s leaves')", notes.wood.c_str(), qUtf8Printable(label));
    MeshModel* layer = document.addNewMesh("", label + " leaves", false);
    add_vertices(layer->cm, notes.leaves);
    layer->UpdateBoxAndNormals();
  };
  auto log_summary = [&](const bridge::LayerNotes& notes) {
    Log("%s", notes.summary.c_str());
    for (const auto& w : notes.warnings) Log(GLLogStream::WARNING, "treeskel: warning: %s", w.c_str());
  };
  if (!mesh) {
    bridge::SkeletonLayer skeleton;
    if (!bridge::tree_skeleton(xyz, sp, mp, progress, skeleton, error)) {
      return fail(QString("Tree Skeleton failed on layer '%1': %2").arg(label, QString::fromStdString(error)));
    }
    add_leaves(skeleton);
    MeshModel* layer = document.addNewMesh("", label + " skeleton", true);
    layer->updateDataMask(MeshModel::MM_VERTQUALITY);
    auto first = add_vertices(layer->cm, skeleton.xyz);
    auto v = first;
    for (double r : skeleton.radius) (v++)->Q() = static_cast<float>(r);
    auto edge = vcg::tri::Allocator<CMeshO>::AddEdges(layer->cm, skeleton.edges.size() / 2);
    for (std::size_t e = 0; e + 1 < skeleton.edges.size(); e += 2, ++edge) {
      edge->V(0) = &*(first + skeleton.edges[e]);
      edge->V(1) = &*(first + skeleton.edges[e + 1]);
    }
    layer->UpdateBoxAndNormals();
    log_summary(skeleton);
    return true;
  }
  bridge::MeshLayer result;
  if (!bridge::tree_mesh(xyz, sp, mp, progress, result, error)) {
    return fail(QString("Tree Mesh failed on layer '%1': %2").arg(label, QString::fromStdString(error)));
  }
  add_leaves(result);
  MeshModel* layer = document.addNewMesh("", label + " tree mesh", true);
  auto first = add_vertices(layer->cm, result.xyz);
  auto face = vcg::tri::Allocator<CMeshO>::AddFaces(layer->cm, result.triangles.size() / 3);
  for (std::size_t t = 0; t + 2 < result.triangles.size(); t += 3, ++face)
    for (int k = 0; k < 3; ++k) face->V(k) = &*(first + result.triangles[t + k]);
  layer->UpdateBoxAndNormals();
  log_summary(result);
  return true;
}

bool FilterTreeskelPlugin::fail(const QString& message) {
  errorMessage = message;  // MeshLab's dialog shows it; meshlabserver prints only the log
  Log(GLLogStream::WARNING, "%s", qUtf8Printable(message));
  return false;
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterTreeskelPlugin)
