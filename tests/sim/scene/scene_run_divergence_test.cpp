// A run that blows up says so (sim/scene/scene_run.h, run_scene_checked): an explicit step far
// above its stability limit grows without bound, and the run must stop and report "diverged"
// (result.finite false, so RESULT.json and the CLI's exit code report it) instead of carrying on
// to 1e14 body sizes while reporting finite. Runs that do not blow up, including a body falling
// far under gravity, must not trip the check.
#include <gtest/gtest.h>

#include <string>

#include "sim/mesh/box_mesher.h"
#include "sim/scene/scene_run.h"
#include "sim/solve/stable_time_step.h"

namespace incise::sim {
namespace {

constexpr Real kSize = 0.02;  // cube edge [m]
constexpr Real kE = 3000, kNu = 0.3, kDensity = 1000;

// A 3 x 3 x 3 cube of model, its base z = 0 clamped unless free, sagging under gravity.
Scene cube_scene(MaterialModel model, Integrator integrator, Real dt, std::int64_t steps,
                 bool free = false) {
  Scene scene;
  scene.mesh.box = {Vec3(kSize, kSize, kSize), Vec3i(3, 3, 3)};
  scene.material = {model, kE, kNu, kDensity, 0.0};
  scene.solver = {integrator, dt, steps, 1e-8};
  scene.gravity = Vec3(0, 0, -9.81);
  if (!free) {
    scene.constraints = {
        {{Box3(Vec3(-1, -1, -1e-9), Vec3(1, 1, 1e-9))}, {true, true, true}, Vec3::Zero()}};
  }
  return scene;
}

TetMesh cube_mesh() {
  return make_box_mesh(Vec3(kSize, kSize, kSize), Vec3i(3, 3, 3));
}

// The estimated explicit limit of the cube (about half the exact one, stable_time_step.h).
Real explicit_limit() {
  return stable_time_step(cube_mesh(), kE, kNu, kDensity);
}

TEST(HardCaseDivergence, SymplecticEulerAtTwentyTimesItsLimitStopsAsDiverged) {
  constexpr std::int64_t kSteps = 2000;
  for (const auto model : {MaterialModel::linear, MaterialModel::neohookean}) {
    const CheckedRun run = run_scene_checked(
        cube_scene(model, Integrator::symplectic_euler, 20 * explicit_limit(), kSteps),
        cube_mesh());
    EXPECT_EQ(run.stop, RunStop::diverged) << run.status;
    EXPECT_FALSE(run.result.finite);
    EXPECT_EQ(run.status.rfind("diverged at step " + std::to_string(run.result.steps + 1) + ":", 0),
              0u)
        << run.status;
    // It stopped at the first step past the limit (measured: step 3, 2.7e3 times the rest size for
    // linear, 5e7 for Neo-Hookean), long before the end, with finite numbers to show for it.
    EXPECT_LT(run.result.steps, kSteps);
    EXPECT_GT(run.peak_extent, kDivergedExtent);
    EXPECT_TRUE(run.result.final_positions.allFinite());
  }
}

TEST(HardCaseDivergence, StableRunsComplete) {
  // Explicit at its limit, and implicit Euler (Neo-Hookean, with the projected tangent) at 10
  // times the limit.
  for (const auto& [integrator, factor] : {std::pair{Integrator::symplectic_euler, 1.0},
                                           std::pair{Integrator::implicit_euler, 10.0}}) {
    const CheckedRun run = run_scene_checked(
        cube_scene(MaterialModel::neohookean, integrator, factor * explicit_limit(), 200),
        cube_mesh());
    EXPECT_EQ(run.stop, RunStop::completed) << run.status;
    EXPECT_EQ(run.status, "completed");
    EXPECT_TRUE(run.result.finite);
    EXPECT_EQ(run.result.steps, 200);
    // A sag of a fraction of a millimetre under a clamped base: the bounding box barely changes
    // (it starts at 1, the rest size).
    EXPECT_GE(run.peak_extent, 1);
    EXPECT_LT(run.peak_extent, 1.01);
    EXPECT_GT(run.result.displacement.col(2).cwiseAbs().maxCoeff(), 0);
  }
}

TEST(HardCaseDivergence, FreeFallIsNotDivergence) {
  // 3 s of free fall: about 44 m, over 1000 times the cube's diagonal, but a rigid motion.
  const Real dt = explicit_limit();
  const auto steps = static_cast<std::int64_t>(3.0 / dt);
  const CheckedRun run = run_scene_checked(
      cube_scene(MaterialModel::linear, Integrator::symplectic_euler, dt, steps, true),
      cube_mesh());
  EXPECT_EQ(run.stop, RunStop::completed) << run.status;
  EXPECT_TRUE(run.result.finite);
  const Real fall = -run.result.displacement.col(2).mean();
  EXPECT_NEAR(fall, 9.81 / 2 * (steps * dt) * (steps * dt), 0.01 * fall);
  EXPECT_LT(run.peak_extent, 1 + 1e-6);
}

TEST(HardCaseDivergence, RunSceneOnReportsADivergedRunAsNotFinite) {
  const Scene scene =
      cube_scene(MaterialModel::linear, Integrator::symplectic_euler, 20 * explicit_limit(), 2000);
  const RunResult result = run_scene_on(scene, cube_mesh());
  const CheckedRun checked = run_scene_checked(scene, cube_mesh());
  EXPECT_FALSE(result.finite);
  EXPECT_EQ(result.steps, checked.result.steps);
}

}  // namespace
}  // namespace incise::sim
