// What every front end tells a model's user: the check of a swept mesh and the warnings, each
// raised by the smallest model that earns it and by no other.
#include "model_warnings.h"
#include "../modeling/model_fixtures.h"

#include "treeskel/modeling/sweep.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace treeskel::cli {
namespace {

/// A model and what `model_warnings` takes, kept together so that a test changes one thing.
struct Model {
  Skeleton skeleton;
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  modeling::TreeMeasurements measurements;
  double breast_height = 1.3;
  modeling::SweepStats sweep;
  modeling::MeshCheck check;
  modeling::SkeletonCoverage coverage;
  bool unite_apart = true;

  explicit Model(Skeleton s) : skeleton(std::move(s)) {
    const modeling::TreeMesh mesh = modeling::sweep_mesh(skeleton, {}, &sweep);
    check = check_swept(mesh, sweep, true);
    coverage = modeling::skeleton_coverage(skeleton, mesh);
    modeling::MeasureOptions mo;
    mo.breast_height = breast_height;
    measurements = modeling::measure_tree(skeleton, nullptr, mo);
  }
  std::vector<std::string> warnings() const {
    return model_warnings({skeleton, up, measurements, breast_height, check, sweep, coverage, unite_apart});
  }
};

/// The one warning expected, which must hold `words`.
void expect_one(const std::vector<std::string>& warnings, const std::string& words) {
  ASSERT_EQ(warnings.size(), 1u) << (warnings.empty() ? std::string("none") : warnings.front());
  EXPECT_NE(warnings.front().find(words), std::string::npos) << warnings.front();
}

TEST(CheckSwept, TakesTheSweepsOwnSelfIntersectionTest) {
  const Skeleton s = test::y_shape(0.1);
  modeling::SweepStats stats;
  const modeling::TreeMesh mesh = modeling::sweep_mesh(s, {}, &stats);
  const modeling::MeshCheck whole = modeling::check_mesh(mesh, true);
  const modeling::MeshCheck swept = check_swept(mesh, stats, true);
  EXPECT_TRUE(swept.ok()) << swept.problem();
  EXPECT_TRUE(swept.self_intersections_checked);
  EXPECT_EQ(swept.self_intersections, whole.self_intersections);
  EXPECT_EQ(swept.faces, whole.faces);
  EXPECT_EQ(swept.components, 1u);
  EXPECT_DOUBLE_EQ(swept.volume, whole.volume);
  // Without the repair no test was made, and the check says so rather than claiming none.
  EXPECT_FALSE(check_swept(mesh, stats, false).self_intersections_checked);
  // A crossing the sweep left is the check's fault.
  modeling::SweepStats crossing = stats;
  crossing.self_intersections = 3;
  EXPECT_FALSE(check_swept(mesh, crossing, true).ok());
}

TEST(OnlyApart, IsSeveralClosedComponentsAndNothingElse) {
  Model m(test::straight(5.0, 0.2));
  ASSERT_TRUE(m.check.ok()) << m.check.problem();
  EXPECT_FALSE(only_apart(m.check));
  modeling::MeshCheck apart = m.check;
  apart.components = 3;
  EXPECT_TRUE(only_apart(apart));
  apart.boundary_edges = 4;
  EXPECT_FALSE(only_apart(apart));
}

TEST(ModelWarnings, AnUprightTreeOfSoundSizeHasNone) {
  const Model m(test::straight(8.0, 0.15));
  EXPECT_TRUE(m.warnings().empty()) << m.warnings().front();
}

TEST(ModelWarnings, EachFaultSaysItsOwnSentence) {
  const Model sound(test::straight(8.0, 0.15));
  {
    Model m = sound;
    m.check.components = 3;
    expect_one(m.warnings(), "2 swept-apart limb(s)");
  }
  {
    Model m = sound;
    m.sweep.pieces_failed = 2;
    expect_one(m.warnings(), "could not be united");
    m.unite_apart = false;
    expect_one(m.warnings(), "--no-unite");
  }
  {
    Model m = sound;
    m.sweep.float_crossings = 5;
    expect_one(m.warnings(), "32-bit floats");
  }
  {
    Model m = sound;
    m.coverage.inside_length = 0.5 * m.coverage.length;
    expect_one(m.warnings(), "only 50% of the skeleton's length");
  }
  {
    Model m = sound;
    m.check.volume = 0.5 * m.measurements.volume;  // the volumes' ratio alone warns of nothing
    EXPECT_TRUE(m.warnings().empty());
    m.coverage.wood.inside = m.coverage.wood.samples / 2;
    expect_one(m.warnings(), "the mesh holds 50% of the wood the fitted radii describe");
  }
  {
    Model m = sound;  // the tree's nodes listed 1,000 points; 200 more were in parts too far to join
    m.skeleton[m.skeleton.root].points.resize(1000);
    m.skeleton.left_out.far_parts = 200;
    expect_one(m.warnings(), "200 of the cloud's 1200 points (17%)");
    m.skeleton.left_out.far_parts = 100;  // 9%: below the tenth
    EXPECT_TRUE(m.warnings().empty());
  }
}

TEST(MeshWarnings, AreTheModelsAboutTheMeshAlone) {
  Model m(test::straight(1.0, 0.02));  // shorter than breast height: a model's warning, not the mesh's
  EXPECT_TRUE(mesh_warnings(m.check, m.sweep, m.coverage, m.unite_apart).empty());
  m.coverage.inside_length = 0.5 * m.coverage.length;
  m.sweep.pieces_failed = 1;
  const auto mesh = mesh_warnings(m.check, m.sweep, m.coverage, m.unite_apart);
  ASSERT_EQ(mesh.size(), 2u);
  const auto model = m.warnings();
  ASSERT_EQ(model.size(), 3u);
  EXPECT_EQ(std::vector<std::string>(model.begin(), model.begin() + 2), mesh);  // first, in the same words
  EXPECT_NE(model.back().find("shorter than breast height"), std::string::npos) << model.back();
}

TEST(MeshWarnings, AMeshThatHoldsLittleOfTheWoodItsRadiiDescribe) {
  Model m(test::y_shape(0.1));  // the arms start inside the trunk: overlapping frustums, no warning
  EXPECT_TRUE(mesh_warnings(m.check, m.sweep, m.coverage, m.unite_apart).empty());
  EXPECT_GT(m.coverage.wood.share(), 0.95);
  // The skeleton's whole length in the mesh, but a tube of half the radii: a quarter of the wood.
  Skeleton thin = m.skeleton;
  for (NodeId v = 0; v < thin.node_count(); ++v) thin[v].radius *= 0.5;
  m.coverage = modeling::skeleton_coverage(m.skeleton, modeling::sweep_mesh(thin));
  EXPECT_GT(m.coverage.share(), 0.99);
  EXPECT_NEAR(m.coverage.wood.share(), 0.25, 0.05);
  expect_one(mesh_warnings(m.check, m.sweep, m.coverage, m.unite_apart), "of the wood the fitted radii describe");
  expect_one(m.warnings(), "of the wood the fitted radii describe");
}

TEST(ModelWarnings, SizesAndAxesNoTreeHas) {
  {
    Model m(test::straight(8.0, 0.15));
    m.up = Eigen::Vector3d::UnitX();  // an upright tree read with the wrong up axis
    expect_one(m.warnings(), "--up");
  }
  {
    const Model m(test::straight(300.0, 0.5));  // metres read as centimetres, or worse
    expect_one(m.warnings(), "300 units tall");
  }
  {
    const Model m(test::straight(8.0, 2.0));  // a 4 m trunk
    expect_one(m.warnings(), "a DBH of 4");
  }
  {
    const Model m(test::straight(1.0, 0.02));
    expect_one(m.warnings(), "shorter than breast height");
  }
}

// The bushes --complete-all leaves out of a leafy or needled crown are said, with how many points
// they hold and the front end's own names; nothing is said when they were grown or not asked for.
TEST(BushesLeftOut, SaysHowManyPointsAndTheFrontEndsWayToTheWood) {
  CompleteStats grafted;
  grafted.bushy_grafts = 27;
  grafted.bushy_points = 30607;
  EXPECT_EQ(bushes_left_out(grafted, 83392), "");  // bushes, but not past the share: not left out by the option
  grafted.leafy_bushes = true;
  const std::string said = bushes_left_out(grafted, 83392);
  EXPECT_EQ(said.rfind("--complete-all: 30607 of the 83392 points lie in bushes", 0), 0u) << said;
  EXPECT_NE(said.find("--wood-only sets the leaves aside"), std::string::npos) << said;
  const std::string python = bushes_left_out(grafted, 83392, "complete_all", "wood_only=True");
  EXPECT_EQ(python.rfind("complete_all: ", 0), 0u) << python;
  EXPECT_NE(python.find("wood_only=True sets"), std::string::npos) << python;
  EXPECT_EQ(python.find("--"), std::string::npos) << python;
}

}  // namespace
}  // namespace treeskel::cli
