// The surgical scenes built from the anatomy: the liver probed, grasped and cut along its marked
// line (on target, no never event, the held side unmoved); the knee inspected through its portals
// with the 30-degree scope and the probe, and its ACL (protected) cut: a never event. The
// palpation block as a surgical scene.

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sim/scene/scene_error.h"
#include "sim/solve/stable_time_step.h"
#include "sim/surgery/scene_presets.h"

namespace incise::sim::surgery {
namespace {

// An orientation whose tool axis d = R e_z is `direction`.
Eigen::Quaternion<Real> pointing(const Vec3& direction) {
  return Eigen::Quaternion<Real>::FromTwoVectors(Vec3::UnitZ(), direction.normalized());
}

ToolInput at(const Vec3& tip, const Vec3& direction, Real jaw = 1) {
  ToolInput in;
  in.tip = tip;
  in.orientation = pointing(direction);
  in.jaw = jaw;
  return in;
}

std::vector<SceneEvent> run(SurgicalScene& scene, int steps,
                            const std::function<std::vector<ToolInput>(Real)>& inputs) {
  std::vector<SceneEvent> events;
  for (int n = 0; n < steps; ++n) {
    const Real s = static_cast<Real>(n) / steps;
    scene.step(inputs(s));
    for (SceneEvent& e : scene.take_events())
      events.push_back(std::move(e));
    if (!scene.state_finite()) break;
  }
  return events;
}

int count(const std::vector<SceneEvent>& events, EventKind kind) {
  int n = 0;
  for (const SceneEvent& e : events)
    n += e.kind == kind ? 1 : 0;
  return n;
}

TEST(LiverScene, ProbedGraspedAndCutAlongTheMarkedLine) {
  LiverSceneOptions options;
  ToolSpec scalpel = make_tool(ToolKind::scalpel, 2);
  scalpel.blade_length = 0.012;
  options.tools = {make_tool(ToolKind::probe, 0), make_tool(ToolKind::grasper, 1), scalpel};
  SurgicalSceneSetup setup = make_liver_surgery(options);
  // The step is the tissue's stable step.
  EXPECT_NEAR(setup.spec.dt,
              stable_time_step(setup.spec.tissue, options.liver.youngs_modulus,
                               options.liver.poisson_ratio, options.liver.density),
              1e-15);
  ASSERT_GE(setup.cut_target.size(), 2u);
  const Vec3 start = setup.cut_target.front(), end = setup.cut_target.back();
  const TetMesh rest_mesh = setup.spec.tissue;
  const std::vector<char> fixed = setup.spec.fixed;
  SurgicalScene scene(std::move(setup.spec));
  const Vec3 down = -Vec3::UnitZ();
  const Vec3 away(0, 0, 0.3);  // far above the organ
  // 1. The probe pressed 5 mm into the surface at the line's start.
  run(scene, 400, [&](Real s) {
    const Vec3 tip = start + Vec3(0, 0, 0.02 - 0.025 * std::min(1.0, 2 * s));
    return std::vector<ToolInput>{at(tip, down), at(away, down), at(away, down)};
  });
  ASSERT_TRUE(scene.state_finite());
  EXPECT_GT(scene.force_model(0).force.z(), 0);  // the organ pushes the hand back up
  // 2. The scalpel along the marked line, its tip 6 mm under the surface, the blade upright.
  const std::vector<SceneEvent> events = run(scene, 800, [&](Real s) {
    const Vec3 tip = start + s * (end - start) - Vec3(0, 0, 0.006);
    return std::vector<ToolInput>{at(away, down), at(away, down), at(tip, down)};
  });
  run(scene, 50, [&](Real) {
    return std::vector<ToolInput>{at(away, down), at(away, down), at(away, down)};
  });
  ASSERT_TRUE(scene.state_finite());
  EXPECT_GT(count(events, EventKind::cut), 0);
  EXPECT_EQ(count(events, EventKind::never_event), 0);
  const tools::DamageMetrics damage = scene.damage();
  EXPECT_GT(damage.cut_area, 0);
  // Cut where marked: within the target's half width on average.
  EXPECT_LT(damage.cut_mean_distance, options.target_half_width);
  EXPECT_FALSE(damage.never_event);
  // The flat side stays where it is held: every held node (their numbers change when the slivers
  // a stroke left are collapsed) is at its rest point, and none was lost.
  const TetMesh& mesh = scene.tissue().mesh();
  int held = 0;
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (!scene.tissue().is_fixed(i)) continue;
    ++held;
    EXPECT_EQ(mesh.x.row(i), mesh.rest.row(i)) << "held node " << i;
  }
  EXPECT_GE(held, static_cast<int>(std::count(fixed.begin(), fixed.end(), 1)));
  (void)rest_mesh;
}

// A condensed far field (operational_radius; FarFieldSpec): under a probe pressed into the
// operational region the organ pushes back as the fully nonlinear one does (the far field's strains
// are small, where linear elasticity holds); a cut along the marked line works, and a stroke that
// runs out of the region ends at its edge, the far field untouched.
TEST(LiverScene, ACondensedFarFieldPushesBackLikeTheFullOrganAndKeepsCutsInside) {
  const auto setup_with = [](Real operational_radius) {
    LiverSceneOptions options;
    options.anatomy.cell_size = 0.01;
    options.operational_radius = operational_radius;
    // The two models compared on the same mesh: no refinement (the far field is never refined).
    options.adaptivity.enabled = false;
    ToolSpec scalpel = make_tool(ToolKind::scalpel, 1);
    scalpel.blade_length = 0.012;
    options.tools = {make_tool(ToolKind::probe, 0), scalpel};
    return make_liver_surgery(options);
  };
  SurgicalSceneSetup full_setup = setup_with(0);
  SurgicalSceneSetup condensed_setup = setup_with(0.05);
  ASSERT_TRUE(condensed_setup.spec.far_field.enabled);
  const Vec3 start = condensed_setup.cut_target.front(), end = condensed_setup.cut_target.back();
  const Vec3 down = -Vec3::UnitZ();
  const Vec3 away(0, 0, 0.3);
  const auto press = [&](Real s) {
    const Vec3 tip = start + Vec3(0, 0, 0.02 - 0.025 * std::min(1.0, 4 * s));
    return std::vector<ToolInput>{at(tip, down), at(away, down)};
  };
  SurgicalScene full(std::move(full_setup.spec));
  SurgicalScene condensed(std::move(condensed_setup.spec));
  const int far_tets = static_cast<int>(
      std::count(condensed.tissue().far_field().begin(), condensed.tissue().far_field().end(), 1));
  EXPECT_GT(far_tets, condensed.tissue().mesh().num_tets() / 4);
  // 5 mm in over 0.25 s, then 0.75 s for the organ to settle (ambient damping 20/s).
  const int steps = static_cast<int>(1.0 / condensed_setup.spec.dt);
  run(full, steps, press);
  run(condensed, steps, press);
  ASSERT_TRUE(full.state_finite() && condensed.state_finite());
  const Vec3 f_full = full.force_model(0).force, f_condensed = condensed.force_model(0).force;
  EXPECT_GT(f_full.z(), 0.05);
  EXPECT_LT((f_condensed - f_full).norm(), 0.05 * f_full.norm())
      << "full " << f_full.transpose() << ", condensed " << f_condensed.transpose();

  // The scalpel along the marked line, 6 mm deep: inside the region, it cuts.
  std::vector<SceneEvent> events = run(condensed, 800, [&](Real s) {
    const Vec3 tip = start + s * (end - start) - Vec3(0, 0, 0.006);
    return std::vector<ToolInput>{at(away, down), at(tip, down)};
  });
  EXPECT_GT(count(events, EventKind::cut), 0);
  EXPECT_EQ(condensed.cuts_outside_region(), 0);
  // On past the line's end, 6 cm further: the stroke ends at the region's edge.
  const Vec3 beyond = end + 0.06 * (end - start).normalized();
  events = run(condensed, 1200, [&](Real s) {
    const Vec3 tip = end + s * (beyond - end) - Vec3(0, 0, 0.006);
    return std::vector<ToolInput>{at(away, down), at(tip, down)};
  });
  run(condensed, 50, [&](Real) { return std::vector<ToolInput>{at(away, down), at(away, down)}; });
  ASSERT_TRUE(condensed.state_finite());
  EXPECT_GT(condensed.cuts_outside_region(), 0);
  EXPECT_EQ(static_cast<int>(std::count(condensed.tissue().far_field().begin(),
                                        condensed.tissue().far_field().end(), 1)),
            far_tets);
  EXPECT_EQ(condensed.tissue().model().name(), "hybrid_condensed");
}

TEST(KneeScene, ScopeAndProbeThroughThePortalsAndTheLigamentIsProtected) {
  KneeSceneOptions options;
  ToolSpec scalpel = make_tool(ToolKind::scalpel, 2);
  scalpel.blade_length = 0.02;
  options.tools = KneeSceneOptions::default_tools();
  options.tools.push_back(scalpel);
  SurgicalSceneSetup setup = make_knee_surgery(options);
  ASSERT_EQ(setup.spec.bones.size(), 2u);
  const Portal* scope_portal = nullptr;
  const Portal* probe_portal = nullptr;
  for (const Portal& p : setup.portals) {
    if (p.name == "anterolateral") scope_portal = &p;
    if (p.name == "anteromedial") probe_portal = &p;
  }
  ASSERT_NE(scope_portal, nullptr);
  ASSERT_NE(probe_portal, nullptr);
  const Vec3 acl = find_landmark(setup.landmarks, "acl_midpoint").position;
  const Vec3 horn = find_landmark(setup.landmarks, "medial_meniscus_anterior_horn").position;
  SurgicalScene scene(std::move(setup.spec));
  const Vec3 away(0, 0.3, 0.3);
  // The scope enters 5 mm through its portal; the probe goes from its portal to the medial
  // meniscus's anterior horn (inside the tissue: it meets the meniscus or a bone on the way).
  const Vec3 reach = horn - probe_portal->position;
  const std::vector<SceneEvent> inspection = run(scene, 300, [&](Real s) {
    return std::vector<ToolInput>{
        at(scope_portal->position + 0.005 * scope_portal->direction, scope_portal->direction),
        at(probe_portal->position + std::min(1.0, 1.5 * s) * reach, reach),
        at(away, -Vec3::UnitZ())};
  });
  ASSERT_TRUE(scene.state_finite());
  const std::optional<ScopeCamera> camera = scene.scope_camera();
  ASSERT_TRUE(camera.has_value());
  EXPECT_NEAR(camera->forward.dot(scope_portal->direction), std::cos(std::numbers::pi / 6), 1e-9);
  // The probe met tissue or bone: the hand feels it.
  EXPECT_GT(scene.force_model(1).force.norm(), 0);
  // The scalpel swept across the ACL: cutting protected tissue is a never event.
  const std::vector<SceneEvent> cut = run(scene, 600, [&](Real s) {
    const Vec3 tip = acl + Vec3(-0.01 + 0.02 * s, 0, -0.01);
    return std::vector<ToolInput>{at(away, -Vec3::UnitZ()), at(away, -Vec3::UnitZ()),
                                  at(tip, -Vec3::UnitZ())};
  });
  ASSERT_TRUE(scene.state_finite());
  EXPECT_GT(count(cut, EventKind::never_event), 0);
  EXPECT_TRUE(scene.damage().never_event);
  (void)inspection;
}

// Mass scaling: a step up to the stable one leaves the tissue as it is; twice the stable step
// makes every density 4 times larger (the total mass with it) and the step exactly that.
TEST(LiverScene, AStepLongerThanTheStableStepScalesTheMasses) {
  LiverSceneOptions options;
  const SurgicalSceneSetup plain = make_liver_surgery(options);
  EXPECT_EQ(plain.mass_scale, 1);
  options.time_step = 0.5 * plain.spec.dt;
  const SurgicalSceneSetup shorter = make_liver_surgery(options);
  EXPECT_EQ(shorter.mass_scale, 1);
  EXPECT_EQ(shorter.spec.dt, plain.spec.dt);
  options.time_step = 2 * plain.spec.dt;
  const SurgicalSceneSetup scaled = make_liver_surgery(options);
  EXPECT_NEAR(scaled.mass_scale, 4, 1e-12);
  EXPECT_NEAR(scaled.spec.dt, 2 * plain.spec.dt, 1e-12 * plain.spec.dt);
  const auto total_mass = [](const SurgicalSceneSetup& setup) {
    return setup.spec.model(setup.spec.tissue)->masses().sum();
  };
  EXPECT_NEAR(total_mass(scaled), 4 * total_mass(plain), 1e-9 * total_mass(plain));
  options.time_step = -1;
  EXPECT_THROW(make_liver_surgery(options), std::invalid_argument);
}

// The palpation block's scene (sim/scenes/palpation.json), written out.
Scene palpation_block() {
  Scene scene;
  scene.mesh.box.size = Vec3(0.08, 0.08, 0.03);
  scene.mesh.box.cells = Vec3i(12, 12, 4);
  scene.material = {MaterialModel::mass_spring, 3000, 0.45, 1000, 0.5, 0};
  Constraint bottom;
  bottom.where.box = {Vec3::Zero(), Vec3(0.08, 0.08, 0)};
  scene.constraints = {bottom};
  scene.tool = SphereTool{0.005, 300, 0};
  scene.solver.dt = 2.5e-4;
  scene.solver.steps = 1;
  return scene;
}

TEST(BlockScene, HeldOnItsFixedFaceWithAProbeOfTheSpheresSizeInEachHand) {
  const SurgicalSceneSetup setup = make_block_surgery(palpation_block());
  EXPECT_EQ(setup.name, "block");
  EXPECT_TRUE(setup.tools_stand_for_any);
  const TetMesh& mesh = setup.spec.tissue;
  ASSERT_EQ(mesh.num_nodes(), 13 * 13 * 5);
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    EXPECT_EQ(setup.spec.fixed[static_cast<std::size_t>(i)] == 1, mesh.rest(i, 2) == 0) << i;
  }
  ASSERT_EQ(setup.spec.tools.size(), 2u);
  for (int d = 0; d < 2; ++d) {
    const ToolSpec& t = setup.spec.tools[static_cast<std::size_t>(d)];
    EXPECT_EQ(t.kind, ToolKind::probe);
    EXPECT_EQ(t.device, d);
    EXPECT_EQ(t.probe.radius, 0.005);
    EXPECT_EQ(t.probe.coupling_stiffness, 300);
    EXPECT_EQ(t.probe.max_force, 20);
  }
  EXPECT_EQ(setup.spec.dt, 2.5e-4);
  EXPECT_EQ(setup.spec.damage_every, 40);  // 10 ms
}

TEST(BlockScene, APressedProbeFeelsTheTissuePushBackHarderTheDeeperItGoes) {
  const SurgicalSceneSetup setup = make_block_surgery(palpation_block());
  const Vec3 top(0.04, 0.04, 0.03 + 0.005);  // the tip's sphere resting on the top face
  std::vector<Real> forces;
  for (const Real depth : {0.002, 0.004}) {
    SurgicalScene scene(setup.spec);
    // Lowered over 0.1 s and held for 0.4 s (the block settles within a few tenths).
    run(scene, 2000, [&](Real s) {
      return std::vector<ToolInput>{
          at(top - std::min(1.0, 5 * s) * depth * Vec3::UnitZ(), -Vec3::UnitZ())};
    });
    const Vec3 f = scene.force_model(0).force;
    // Up, and less than the coupling alone would give (the tissue gives way under the tip).
    EXPECT_GT(f.z(), 0);
    EXPECT_LT(f.z(), 300 * depth);
    EXPECT_LT(std::hypot(f.x(), f.y()), 1e-3 * f.z());
    forces.push_back(f.z());
    EXPECT_TRUE(scene.state_finite());
  }
  EXPECT_GT(forces[1], 1.5 * forces[0]);
}

// A hard case: the device swept through the middle of the block at 1 m/s, in one side and out of
// the other. The probe's proxy cannot follow it through (it never tunnels): it drags the tissue
// along, saturated, and the block stays finite and calms down once the device is gone.
TEST(BlockScene, ADeviceSweptThroughTheBlockAtOneMetrePerSecondLeavesItFiniteAndCalm) {
  SurgicalScene scene(make_block_surgery(palpation_block()).spec);
  const Real dt = 2.5e-4;
  const Vec3 start(-0.01, 0.04, 0.015);
  const Vec3 velocity(1, 0, 0);  // [m/s]
  const auto max_speed = [&] { return scene.tissue().mesh().v.rowwise().norm().maxCoeff(); };
  const int sweep = static_cast<int>(std::lround(0.1 / (velocity.x() * dt)));
  Real peak = 0;
  Real peak_force = 0;
  for (int s = 1; s <= sweep; ++s) {
    scene.step(std::vector<ToolInput>{at(start + velocity * (s * dt), -Vec3::UnitZ())});
    ASSERT_TRUE(scene.state_finite()) << "step " << s;
    ASSERT_TRUE(scene.force_model(0).force.allFinite());
    peak = std::max(peak, max_speed());
    peak_force = std::max(peak_force, scene.force_model(0).force.norm());
  }
  EXPECT_GT(peak_force, 1);  // it did hit the tissue
  EXPECT_LE(peak_force, 20 + 1e-9);
  EXPECT_GT(peak, 0.1);  // and shook it
  for (int s = 0; s < 4000; ++s)
    scene.step(std::vector<ToolInput>{at(Vec3(-1, -1, -1), -Vec3::UnitZ())});
  ASSERT_TRUE(scene.state_finite());
  EXPECT_LT(max_speed(), 1e-3 * peak);
}

TEST(BlockScene, WhatALiveBlockCannotCarryIsRefusedByItsKey) {
  const auto refused = [](const std::function<void(Scene&)>& change, const std::string& key) {
    Scene scene = palpation_block();
    change(scene);
    try {
      make_block_surgery(scene);
      ADD_FAILURE() << key << " accepted";
    } catch (const SceneError& e) {
      EXPECT_EQ(e.path(), key);
    }
  };
  refused([](Scene& s) { s.loads.push_back({s.constraints[0].where, Vec3(0, 0, -1)}); }, "loads");
  refused([](Scene& s) { s.constraints[0].axes = {true, true, false}; }, "constraints[0]");
  refused([](Scene& s) { s.constraints[0].displacement = Vec3(0, 0, 0.001); }, "constraints[0]");
  refused([](Scene& s) { s.solver.integrator = Integrator::implicit_euler; }, "solver.integrator");
  refused(
      [](Scene& s) {
        s.constraints[0].where.box = {Vec3(1, 1, 1), Vec3(2, 2, 2)};
      },
      "constraints[0].where");
  refused(
      [](Scene& s) {
        s.mesh.source = MeshSource::file;
        s.mesh.file = "block.msh";
      },
      "mesh");
}

}  // namespace
}  // namespace incise::sim::surgery
