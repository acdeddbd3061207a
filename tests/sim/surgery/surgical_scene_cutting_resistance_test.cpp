// The scalpel's cutting resistance in a surgical scene (sim/surgery/
// surgical_scene_cutting_resistance.cpp): on a block at rest, the hand's force model is the
// toughness of the label cut times the blade's depth, against the blade's motion, and nothing once
// the blade is out; along the shipped liver script, the blade is as deep as its tip is under the
// marked line, the force opposes the stroke, is zero out of the tissue and while the blade moves
// along its own axis, and the work the hand does over the stroke is the toughness times the area
// the blade swept in the tissue (passive at every step); out-of-range toughness is refused.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sim/mesh/box_mesher.h"
#include "sim/scene/scene_run.h"
#include "sim/solve/stable_time_step.h"
#include "sim/surgery/scene_file.h"
#include "sim/surgery/surgical_scene.h"
#include "sim/surgery/tool_script.h"
#include "sim/surgery/track_sampling.h"

namespace incise::sim::surgery {
namespace {

const Vec3 kSize(0.06, 0.06, 0.03);

// A 6 x 6 x 3 cm block held at its base, at rest (no gravity): tissue label 1 for x < 3 cm, 2
// beyond; a scalpel with a 2 cm blade on device 0.
SurgicalSceneSpec labelled_block() {
  SurgicalSceneSpec spec;
  spec.tissue = make_box_mesh(kSize, Vec3i(6, 6, 3));
  for (int t = 0; t < spec.tissue.num_tets(); ++t) {
    Real x = 0;
    for (int k = 0; k < 4; ++k)
      x += spec.tissue.rest(spec.tissue.tets(t, k), 0) / 4;
    spec.tissue.labels(t) = x < kSize.x() / 2 ? 1 : 2;
  }
  spec.fixed.assign(static_cast<std::size_t>(spec.tissue.num_nodes()), 0);
  for (int i = 0; i < spec.tissue.num_nodes(); ++i) {
    if (spec.tissue.rest(i, 2) == 0) spec.fixed[static_cast<std::size_t>(i)] = 1;
  }
  Scene scene;
  scene.material.model = MaterialModel::corotational;
  scene.material.youngs_modulus = 5000;
  scene.material.poisson_ratio = 0.3;
  scene.material.density = 1000;
  scene.material.damping = 0.5;
  spec.model = [scene](const TetMesh& mesh) { return make_model(scene, mesh); };
  spec.dt = 1e-4;
  spec.wave_speed = p_wave_speed(5000, 0.3, 1000);
  spec.damping_time =
      0.5 * element_lengths(spec.tissue.rest, spec.tissue.tets).min_altitude / spec.wave_speed;
  ToolSpec scalpel = make_tool(ToolKind::scalpel, 0);
  scalpel.blade_length = 0.02;
  spec.tools = {scalpel};
  spec.toughness = {{1, 100}, {2, 400}};
  spec.default_toughness = 0;
  return spec;
}

// The blade upright (d = -z), its tip at `tip`.
ToolInput upright(const Vec3& tip) {
  ToolInput in;
  in.tip = tip;
  in.orientation = Eigen::Quaternion<Real>(Eigen::AngleAxis<Real>(std::numbers::pi, Vec3::UnitX()));
  return in;
}

// The blade's tip 1 cm under the top at x, drawn along y from y0 to y1 at 0.2 m/s, then held there
// (1 cm beyond the block) for 100 steps. Checks the force model at every step where the blade is
// well inside (y within 1.5 cm of the middle): the toughness of the label at x times 1 cm, against
// the motion; and that it is zero at the end.
void draw(SurgicalScene& scene, Real x, Real y0, Real y1, Real toughness) {
  const Real dt = 1e-4, speed = 0.2;
  const int steps = static_cast<int>(std::lround(std::abs(y1 - y0) / (speed * dt)));
  const Real sign = y1 > y0 ? 1 : -1;
  int checked = 0;
  for (int n = 1; n <= steps + 100; ++n) {
    const Real y = n <= steps ? y0 + sign * speed * dt * n : y1;
    const ToolInput in = upright(Vec3(x, y, 0.02));
    scene.step(std::span(&in, 1));
    const tools::LocalForceModel model = scene.force_model(0);
    ASSERT_LE(model.force.dot(sign * Vec3::UnitY()), 0) << "y = " << y;  // never pushes along
    if (std::abs(y - kSize.y() / 2) < 0.015 && n <= steps) {
      EXPECT_NEAR(scene.tool_view(0).blade_depth, 0.01, 1e-9) << "y = " << y;
      EXPECT_LT((model.force - Vec3(0, -sign * toughness * 0.01, 0)).norm(), 1e-9)
          << "y = " << y << ": " << model.force.transpose();
      EXPECT_EQ(model.stiffness, Mat3::Zero());
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
  // Out of the tissue: nothing.
  EXPECT_EQ(scene.tool_view(0).blade_depth, 0);
  EXPECT_EQ(scene.force_model(0).force, Vec3::Zero());
}

TEST(SurgicalSceneCuttingResistance, EachLabelResistsWithItsToughnessAgainstTheBladesMotion) {
  SurgicalScene scene(labelled_block());
  // Not yet placed, and placed above the block: no force.
  EXPECT_EQ(scene.force_model(0).force, Vec3::Zero());
  const ToolInput above = upright(Vec3(0.0137, -0.01, 0.05));
  scene.step(std::span(&above, 1));
  EXPECT_EQ(scene.force_model(0).force, Vec3::Zero());
  // Label 1 (100 J/m^2) along +y: 1 N back along -y; label 2 (400 J/m^2) along -y: 4 N along +y.
  draw(scene, 0.0137, -0.01, 0.07, 100);
  draw(scene, 0.0437, 0.07, -0.01, 400);
  EXPECT_TRUE(scene.state_finite());
}

TEST(SurgicalSceneCuttingResistance, InputsInGapsGiveASteadyForceNotAFlicker) {
  // A station's device states arrive in gaps (its deadband): here a new tip every 8th step, the
  // same one (to round-off) in between. The resistance stays on between them, at the toughness
  // times the depth (label 1: 100 J/m^2 x 1 cm = 1 N), and never pushes along the motion.
  SurgicalScene scene(labelled_block());
  const Real dt = 1e-4, speed = 0.2;
  Real y = -0.01;
  int steady = 0;
  for (int n = 1; n <= 4000 && y < 0.07; ++n) {
    if (n % 8 == 0) y += 8 * speed * dt;
    // Between two inputs the tip still moves by round-off (the live engine interpolates between
    // two equal inputs): that is standing still, not a new velocity.
    const Real wiggle = n % 8 == 0 ? 0 : (n % 2) * 1e-15;
    const ToolInput in = upright(Vec3(0.0137, y + wiggle, 0.02));
    scene.step(std::span(&in, 1));
    const Vec3 force = scene.force_model(0).force;
    ASSERT_LE(force.y(), 0) << "y = " << y;
    if (std::abs(y - kSize.y() / 2) < 0.015) {
      EXPECT_NEAR(force.y(), -1.0, 1e-9) << "step " << n << ", y = " << y;
      ++steady;
    }
  }
  EXPECT_GT(steady, 500);
}

// The height of a polyline over the point: linear between its points, by p's projection on the
// segment it is nearest (the liver's marked line, its points on the surface).
Real surface_height(const std::vector<Vec3>& line, const Vec3& p) {
  Real best = std::numeric_limits<Real>::infinity(), z = 0;
  for (std::size_t k = 0; k + 1 < line.size(); ++k) {
    const Vec3 a = line[k], b = line[k + 1];
    const Eigen::Vector2d ab = (b - a).head<2>(), ap = (p - a).head<2>();
    const Real s = std::clamp(ap.dot(ab) / ab.squaredNorm(), Real(0), Real(1));
    const Real distance = (ap - s * ab).norm();
    if (distance < best) {
      best = distance;
      z = a.z() + s * (b.z() - a.z());
    }
  }
  return z;
}

// The shipped liver scene and script (the scalpel on device 2 enters the marked line's start
// 6 mm deep, draws along it at 11 cm/s and withdraws), stepped as `incise surgery` steps them.
TEST(SurgicalSceneCuttingResistance, AlongTheLiverScriptTheHandDoesTheWorkOfTheCut) {
  SurgicalSceneSetup setup = read_surgical_scene(INCISE_SCENES_DIR "/surgery/liver_surgery.json");
  const ToolScript script =
      read_tool_script(INCISE_SCENES_DIR "/surgery/scripts/liver_cut.json", setup);
  int blade = -1;
  for (std::size_t k = 0; k < setup.spec.tools.size(); ++k) {
    if (setup.spec.tools[k].kind == ToolKind::scalpel) blade = static_cast<int>(k);
  }
  ASSERT_GE(blade, 0);
  const int device = setup.spec.tools[static_cast<std::size_t>(blade)].device;
  ASSERT_EQ(setup.spec.toughness.size(), 2u);  // the liver and the gallbladder bed, alike
  const Real toughness = setup.spec.toughness[0].toughness;
  EXPECT_EQ(toughness, 200);
  const tools::CuttingResistanceSettings settings = setup.spec.cutting;
  const Real dt = setup.spec.dt;
  const Vec3 stroke = setup.cut_target.back() - setup.cut_target.front();
  const std::vector<Vec3> line = setup.cut_target;
  SurgicalScene scene(std::move(setup.spec));

  const auto steps = static_cast<int>(std::ceil(script.duration / dt - 1e-9));
  std::vector<ToolInput> inputs;
  sample_script(script, 0, inputs);
  Vec3 tip = inputs[static_cast<std::size_t>(device)].tip;
  Real work = 0, swept = 0, deepest = 0;
  int cutting = 0, along_axis = 0;
  for (int n = 0; n < steps; ++n) {
    const Real t = (n + 1) * dt;
    sample_script(script, t, inputs);
    scene.step(inputs);
    ASSERT_TRUE(scene.state_finite()) << "t = " << t;
    const Vec3 dx = inputs[static_cast<std::size_t>(device)].tip - tip;
    tip = inputs[static_cast<std::size_t>(device)].tip;
    const ToolView view = scene.tool_view(blade);
    const Vec3 force = scene.force_model(device).force;
    // Passive at every step: the hand never gets energy from the cut.
    ASSERT_LE(force.dot(dx), 1e-15 * force.norm() * dx.norm()) << "t = " << t;
    work += force.dot(dx);
    const Real depth = view.blade_depth;
    deepest = std::max(deepest, depth);
    const Vec3 across = dx - dx.dot(view.direction) * view.direction;  // the motion that cuts
    if (t < 0.02 || t > 0.47) {
      // Above the organ before the entry, out again after the withdrawal.
      EXPECT_EQ(depth, 0) << "t = " << t;
      EXPECT_EQ(force, Vec3::Zero()) << "t = " << t;
    } else if (depth > 0 && across.norm() < 1e-12) {
      // Pushed in point first or drawn out along its axis: no new surface, no resistance.
      EXPECT_LT(force.norm(), 1e-9) << "t = " << t;
      ++along_axis;
    } else if (t > 0.08 && t < 0.38) {
      // Drawn along the line in the tissue: back against the stroke, G depth at this speed.
      // As deep as the tip is under the marked line (its ink dots on the surface, at rest; the
      // scalpel does not move the tissue): 6 mm at its ends, more where the surface bulges over
      // the straight stroke between them.
      EXPECT_NEAR(depth, surface_height(line, tip) - tip.z(), 2e-4) << "t = " << t;
      EXPECT_GT(across.norm() / dt, settings.ramp_speed);
      EXPECT_NEAR(force.norm(), toughness * depth, 1e-9 * toughness * depth) << "t = " << t;
      EXPECT_NEAR(force.normalized().dot(across.normalized()), -1, 1e-12) << "t = " << t;
      EXPECT_LT(force.normalized().dot(stroke.normalized()), -0.99) << "t = " << t;
      ++cutting;
    }
    // The fracture view: at speed the work is G times the area the blade's part in the tissue
    // swept across its edge; the ramp scales what is below it.
    swept += depth * across.norm() * std::min(Real(1), across.norm() / dt / settings.ramp_speed);
  }
  std::printf("work %.4g J over %.1f mm^2 swept (deepest %.2f mm), %.4g J/m^2\n", work, swept * 1e6,
              deepest * 1e3, -work / swept);
  EXPECT_GT(cutting, 1000);
  EXPECT_GT(along_axis, 50);
  EXPECT_LT(work, 0);
  EXPECT_NEAR(work, -toughness * swept, 1e-9 * toughness * swept);
  // The blade 6 mm under the marked line over its 4 cm: about 240 mm^2.
  // The blade 6 to 8 mm under the marked line over its 4 cm.
  EXPECT_GT(swept, 0.006 * stroke.norm());
  EXPECT_LT(swept, 0.008 * stroke.norm());
  EXPECT_GT(deepest, 0.006);
}

TEST(SurgicalSceneCuttingResistance, ToughnessOutOfRangeIsRefusedWithTheField) {
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  const Real inf = std::numeric_limits<Real>::infinity();
  struct Case {
    void (*edit)(SurgicalSceneSpec&, Real);
    Real value;
    const char* error;
  };
  const Case cases[] = {
      {[](SurgicalSceneSpec& s, Real v) { s.toughness[1].toughness = v; }, -1,
       "surgical scene: toughness[1].toughness must be >= 0"},
      {[](SurgicalSceneSpec& s, Real v) { s.toughness[0].toughness = v; }, nan,
       "surgical scene: toughness[0].toughness must be >= 0"},
      {[](SurgicalSceneSpec& s, Real v) { s.toughness[0].toughness = v; }, inf,
       "surgical scene: toughness[0].toughness must be >= 0"},
      {[](SurgicalSceneSpec& s, Real) { s.toughness[1].label = 1; }, 0,
       "surgical scene: toughness[1].label 1 is listed twice"},
      {[](SurgicalSceneSpec& s, Real v) { s.default_toughness = v; }, -0.5,
       "surgical scene: default_toughness must be >= 0"},
      {[](SurgicalSceneSpec& s, Real v) { s.cutting.ramp_speed = v; }, 0,
       "surgical scene: cutting.ramp_speed must be > 0"},
      {[](SurgicalSceneSpec& s, Real v) { s.cutting.max_force = v; }, inf,
       "surgical scene: cutting.max_force must be > 0"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.error);
    SurgicalSceneSpec spec = labelled_block();
    c.edit(spec, c.value);
    try {
      SurgicalScene scene(std::move(spec));
      ADD_FAILURE() << "accepted";
    } catch (const std::invalid_argument& error) {
      EXPECT_EQ(std::string(error.what()), c.error);
    }
  }
  // Zero toughness is allowed: that tissue cuts freely.
  SurgicalSceneSpec free = labelled_block();
  free.toughness = {{1, 0}, {2, 0}};
  SurgicalScene scene(std::move(free));
  for (int n = 0; n < 500; ++n) {
    const ToolInput in = upright(Vec3(0.0137, 0.02 + 0.2e-4 * n, 0.02));
    scene.step(std::span(&in, 1));
    EXPECT_EQ(scene.force_model(0).force, Vec3::Zero());
  }
  EXPECT_NEAR(scene.tool_view(0).blade_depth, 0.01, 1e-9);
}

}  // namespace
}  // namespace incise::sim::surgery
