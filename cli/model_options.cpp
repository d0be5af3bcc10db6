#include "model_options.h"

#include "report.h"

#include "treeskel/complete.h"
#include "treeskel/modeling/measurements.h"

namespace treeskel::cli {

void add_model_options(CLI::App& c, ModelSettings& s) {
  const char* g = "Model";
  auto& r = s.radii;
  auto& w = s.sweep;
  c.add_flag("--with-skeleton", s.with_skeleton, "Put the skeleton into the mesh file as lines beside the mesh")->group(g);
  c.add_flag("--allow-defects", s.allow_defects, "Write the mesh even if it fails its checks (closed, manifold, ...)")
      ->group(g);
  c.add_option("--exponent", r.exponent, "Leonardo exponent e: r_parent^e = sum of r_child^e at forks (2: pipe model)")
      ->default_val(r.exponent)->check(in_range(1.0, 4.0))->group(g);
  c.add_option("--tip-weight", r.tip_weight,
               "Pipe model: what a tip carries, in median twig lengths (large: all twigs equally thick)")
      ->default_val(r.tip_weight)->check(positive())->group(g);
  c.add_option("--stem-share-bound", r.max_share_over_pipe,
               "At each fork on the stem, let no branch take more than K times the share of the stem's cross "
               "section that the pipe model gives it (0: off, else at least 1). Circle fits around a side branch "
               "that take in needles, leaves or scattered points come out as wide as the stem; unbounded, the stem "
               "above such forks thins far faster than its points (docs/models.md)")
      ->default_val(r.max_share_over_pipe)->check(off_or_at_least(1.0))->group(g);
  c.add_option("--stub-length", r.stub_length,
               "A tip shorter than K radii of the branch it leaves is a stub: the radii are fitted without it, and "
               "it is hung back as a cylinder carrying its own length only in the pipe model (its circle fits, of the "
               "points of the branch it sticks out of, are not used). The level sets of sparse or unevenly scanned "
               "trunks leave such spurs, and as twigs each took a twig's share of the trunk (0: every tip is a twig; "
               "docs/models.md)")
      ->default_val(r.stub_length)->check(not_negative())->group(g);
  c.add_option("--fork-margin", r.fork_margin,
               "Along a branch that ends in a fork, leave out of its taper the circle fits within K of their own radii "
               "of the fork: the level sets split there and the last node's circle comes out small, which pulled the "
               "branch and all it carries thinner (0: every fit counts; docs/models.md)")
      ->default_val(r.fork_margin)->check(not_negative())->group(g);
  c.add_option("--stiffness", r.stiffness,
               "Smooth each limb's path over K times its radius once the radii are fitted: a trunk or limb then "
               "bends no more sharply than its thickness allows, where a sparse scan's skeleton wandered from twig "
               "to twig; twigs keep their bends (0: the skeleton's path as it is)")
      ->default_val(r.stiffness)->check(not_negative())->group(g);
  c.add_option("--fit-points", r.min_points, "Fewest points of a node for its radius to be measured by a circle fit")
      ->default_val(r.min_points)->check(in_range(3, 100000))->group(g);
  c.add_option("--segments", w.trunk_segments, "Polygon sides around the trunk; thinner branches get fewer")
      ->default_val(w.trunk_segments)->check(in_range(3, 256))->group(g);
  c.add_option("--min-segments", w.min_segments, "Fewest polygon sides around a branch")
      ->default_val(w.min_segments)->check(in_range(3, w.max_segments))->group(g);
  c.add_option("--min-radius", w.min_radius, "Leave out branches thinner than this where they start (0: keep all)")
      ->default_val(w.min_radius)->check(not_negative())->group(g);
  c.add_option("--breast-height", s.breast_height, "Height above the base where the DBH is measured (1.3 for metres)")
      ->default_val(s.breast_height)->check(positive())->group(g);
  c.add_flag("--dbh-from-model", s.dbh_from_model,
             "Take the DBH from the model's radius at breast height, not from a circle fitted to the points of "
             "a slice there (the default; the model's radius is the fallback when that circle is unreliable)")
      ->group(g);
  c.add_flag("--no-unite", [&s](std::int64_t) { s.sweep.unite_apart = false; },
             "Leave out the limbs a fork's join or a crossing leaves no room for, instead of sweeping them apart and "
             "uniting them with the tree (much faster on crowded crowns; the summary says how much of the skeleton "
             "is then missing)")
      ->group(g);
  c.add_flag("--complete", r.complete,
             "Grow branches through the points that lie more than an octree cell outside the model's tubes (crowded "
             "or sparsely scanned crowns: the mesh then reaches them), and fit the radii again. Tufts on the bark "
             "(reaching at most three cells out: noise) and bushes (more than two forks a band: leaves, needles) "
             "are not grown (--complete-all grows them). Off by default: a few more points within 1% of the model, at up to 3x the time where "
             "the new twigs cross other limbs (docs/models.md). Needs a cloud, not a saved skeleton")
      ->group(g);
  c.add_flag("--complete-all", [&r](std::int64_t) {
               r.complete = true;
               r.completion = all_grafts();
             },
             "As --complete, and grow the tufts and bushes too: a twig through every group of 4 or more points "
             "more than an octree cell outside the tubes, as AdTree's models reach every cluster of points. On "
             "AdTree's samples 0.87-0.996 of the points then lie within 1% of the height of the mesh (0.75-0.995 "
             "by default), at 1.1-6 times the default's time, and the wood volume grows by 2-8%: leaves and noise "
             "become twigs. Where bushes hold more than a fifth of the points (a leafy or needled crown) they are "
             "left out, with a warning: set the leaves aside first (--wood-only; docs/models.md)")
      ->group(g);
  c.add_flag("--local", s.local,
             "Write the mesh in the local frame (the input's frame less the offset the report gives) in every format. "
             "By default OBJ holds the input's frame in double precision, glTF local vertices under a root node "
             "that turns the up axis to +Y and translates by the offset exactly, PLY and STL the input's frame "
             "unless 32-bit floats would round it (georeferenced clouds), then local with a note")
      ->group(g);
  c.add_flag("--no-repair", [&s](std::int64_t) { s.sweep.repair = false; },
             "Skip the self-intersection test and repair (faster; the mesh may then cross itself)")->group(g);
}

nlohmann::ordered_json measurements_json(const modeling::TreeMeasurements& m) {
  nlohmann::ordered_json j;
  j["height"] = m.height;
  j["dbh"] = m.dbh ? nlohmann::ordered_json(*m.dbh) : nlohmann::ordered_json(nullptr);
  j["dbh_source"] = m.dbh_source == modeling::DbhSource::points  ? nlohmann::ordered_json("points")
                    : m.dbh_source == modeling::DbhSource::model ? nlohmann::ordered_json("model")
                                                                 : nlohmann::ordered_json(nullptr);
  j["breast_height"] = m.breast_height;
  j["dbh_height"] = m.dbh ? nlohmann::ordered_json(m.dbh_height) : nlohmann::ordered_json(nullptr);
  j["volume"] = m.volume;
  j["length"] = m.length;
  j["trunk_length"] = m.trunk_length;
  j["branches_by_order"] = m.branches_by_order;
  j["cylinders"] = m.cylinders.size();
  return j;
}

}  // namespace treeskel::cli
