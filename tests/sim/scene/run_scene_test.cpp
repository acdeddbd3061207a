#include "sim/scene/run_scene.h"

#include <gtest/gtest.h>

#include <cmath>

#include "sim/scene/scene_error.h"

namespace incise::sim {
namespace {

Scene hanging_bar(Real dt, std::int64_t steps) {
  Scene scene;
  scene.mesh.box = {Vec3(0.06, 0.02, 0.02), Vec3i(6, 2, 2)};
  scene.material = {MaterialModel::mass_spring, 3000, 0.45, 1000, 0.3};
  scene.constraints = {
      {{Box3(Vec3::Zero(), Vec3(0, 0.02, 0.02))}, {true, true, true}, Vec3::Zero()}};
  scene.gravity = Vec3(0, 0, -9.81);
  scene.solver = {Integrator::symplectic_euler, dt, steps};
  return scene;
}

TEST(RunScene, ReportsTheFinalStateAndTiming) {
  const RunResult result = run_scene(hanging_bar(1e-4, 200));
  EXPECT_TRUE(result.finite);
  EXPECT_EQ(result.steps, 200);
  EXPECT_EQ(result.rest.rows(), 7 * 3 * 3);
  EXPECT_EQ(result.displacement.rows(), result.rest.rows());
  EXPECT_EQ(result.num_tets, 5 * 6 * 2 * 2);
  EXPECT_GT(result.ms_per_step, 0);
  EXPECT_LT(result.ms_per_step, 100);
  EXPECT_GT(result.max_speed, 0);
  EXPECT_LT(result.displacement.col(2).minCoeff(), 0);                // the free end drops
  EXPECT_EQ(result.displacement.row(0), Eigen::RowVector3d::Zero());  // clamped
}

TEST(RunScene, StopsWhenTheStateStopsBeingFinite) {
  // Far above the explicit stability limit (about l sqrt(D / E) / 2 = 2.9e-4 s): it blows up.
  const RunResult result = run_scene(hanging_bar(0.05, 100000));
  EXPECT_FALSE(result.finite);
  EXPECT_LT(result.steps, 100000);
  EXPECT_GE(result.steps, 1);
}

TEST(RunScene, InvalidSceneThrowsSceneError) {
  EXPECT_THROW(run_scene(hanging_bar(-1, 10)), SceneError);
}

}  // namespace
}  // namespace incise::sim
