// The surgical scenes built from the anatomy: the liver probed, grasped and cut along its marked
// line (on target, no never event, the held side unmoved); the knee inspected through its portals
// with the 30-degree scope and the probe, and its ACL (protected) cut: a never event.

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace incise::sim::surgery
