#include "sim/scene/simulation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "sim/scene/node_selection.h"
#include "sim/scene/scene_error.h"

namespace incise::sim {
namespace {

constexpr Real kSide = 0.04;  // [m]

Selection select(const Vec3& low, const Vec3& high) {
  return {Box3(low, high)};
}

// A soft cube of tissue on a grid of 4^3 cells, nothing attached.
Scene free_cube() {
  Scene scene;
  scene.mesh.box = {Vec3::Constant(kSide), Vec3i(4, 4, 4)};
  scene.material = {MaterialModel::mass_spring, 3000, 0.45, 1000, 0.5};
  scene.solver = {Integrator::symplectic_euler, 1e-4, 10000};
  return scene;
}

Scene clamped_cube_under_gravity() {
  Scene scene = free_cube();
  scene.constraints = {
      {select(Vec3::Zero(), Vec3(kSide, kSide, 0)), {true, true, true}, Vec3::Zero()}};
  scene.gravity = Vec3(0, 0, -9.81);
  return scene;
}

std::vector<int> top_nodes(const Simulation& simulation) {
  const Points& rest = simulation.mesh().rest;
  return nodes_in_box(rest, Box3(Vec3(0, 0, kSide), Vec3::Constant(kSide)),
                      selection_tolerance(rest));
}

TEST(Simulation, ClampedCubeUnderGravitySettlesSaggingDownwards) {
  const Scene scene = clamped_cube_under_gravity();
  Simulation simulation(scene);
  Real peak = 0;
  for (std::int64_t step = 0; step < scene.solver.steps; ++step) {
    simulation.step();
    peak = std::max(peak, simulation.max_speed());
  }
  ASSERT_TRUE(simulation.state_finite());
  EXPECT_GT(peak, 1e-2);                           // it did move
  EXPECT_LT(simulation.max_speed(), 1e-6 * peak);  // and came to rest
  const TetMesh& mesh = simulation.mesh();
  Vec3 top = Vec3::Zero();
  for (const int i : top_nodes(simulation))
    top += row3(mesh.x, i) - row3(mesh.rest, i);
  top /= static_cast<Real>(top_nodes(simulation).size());
  // Sags by about rho g L^2 / (2 E) = 2.6 mm for a column of E; down, not sideways.
  EXPECT_LT(top.z(), -1e-3);
  EXPECT_GT(top.z(), -5e-3);
  EXPECT_LT(top.head<2>().norm(), 1e-6 * std::abs(top.z()));
  // The clamped base has not moved at all.
  for (const int i : nodes_in_box(mesh.rest, Box3(Vec3::Zero(), Vec3(kSide, kSide, 0)), 0)) {
    EXPECT_EQ(row3(mesh.x, i), row3(mesh.rest, i));
  }
}

TEST(Simulation, FixingOneAxisLeavesTheOthersFree) {
  // On a frictionless floor (base fixed in z only) the cube spreads sideways as it settles.
  Scene scene = clamped_cube_under_gravity();
  scene.constraints[0].axes = {false, false, true};
  Simulation simulation(scene);
  for (int step = 0; step < 2000; ++step)
    simulation.step();
  const TetMesh& mesh = simulation.mesh();
  const int origin = 0;
  EXPECT_EQ(mesh.x(origin, 2), 0);
  EXPECT_LT(mesh.x(origin, 0), -1e-5);  // the corner moved outwards in x and y
  EXPECT_LT(mesh.x(origin, 1), -1e-5);
}

TEST(Simulation, FreeBodyFallsAsAWholeUnderGravity) {
  Scene scene = free_cube();
  scene.gravity = Vec3(0, 0, -9.81);
  Simulation simulation(scene);
  const int steps = 500;
  for (int step = 0; step < steps; ++step)
    simulation.step();
  const Vec3 expected = steps * scene.solver.dt * scene.gravity;
  for (int i = 0; i < simulation.mesh().num_nodes(); ++i) {
    EXPECT_LT((row3(simulation.mesh().v, i) - expected).norm(), 1e-12);
  }
}

TEST(Simulation, LoadIsSplitEquallyAndChangesMomentumByItsImpulse) {
  Scene scene = free_cube();
  const Vec3 force(0.02, -0.01, 0.03);  // [N], on the top face
  scene.loads = {{select(Vec3(0, 0, kSide), Vec3::Constant(kSide)), force}};
  Simulation simulation(scene);
  const std::vector<int> top = top_nodes(simulation);
  ASSERT_EQ(top.size(), 25u);
  for (const int i : top) {
    EXPECT_TRUE(row3(simulation.external_forces(), i).isApprox(force / 25, 1e-15));
  }
  EXPECT_TRUE(Vec3(simulation.external_forces().colwise().sum().transpose()).isApprox(force));

  const int steps = 300;
  for (int step = 0; step < steps; ++step)
    simulation.step();
  const VecX& m = simulation.model().masses();
  const Vec3 momentum = (simulation.mesh().v.transpose() * m);
  // Internal forces cancel, so the momentum is the load's impulse.
  EXPECT_TRUE(momentum.isApprox(steps * scene.solver.dt * force, 1e-9));
}

TEST(Simulation, DisplacementIsRampedOverHalfTheStepsThenHeld) {
  Scene scene = free_cube();
  scene.solver.steps = 100;  // ramp over 50 steps
  const Vec3 pull(0.004, 0, 0);
  scene.constraints = {
      {select(Vec3::Zero(), Vec3(0, kSide, kSide)), {true, true, true}, Vec3::Zero()},
      {select(Vec3(kSide, 0, 0), Vec3::Constant(kSide)), {true, false, false}, pull}};
  Simulation simulation(scene);
  const int corner = 4;  // node (4, 0, 0)
  ASSERT_EQ(simulation.mesh().rest(corner, 0), kSide);
  for (int step = 1; step <= 80; ++step) {
    simulation.step();
    const Real expected = kSide + pull.x() * std::min(step, 50) / 50.0;
    ASSERT_NEAR(simulation.mesh().x(corner, 0), expected, 1e-15) << "step " << step;
  }
  // y and z of the pulled face were not prescribed: the face narrows (Poisson effect).
  EXPECT_NE(simulation.mesh().x(corner, 1), 0);
}

TEST(Simulation, SelectionsThatPickNoNodeAreSceneErrors) {
  Scene scene = free_cube();
  scene.constraints = {
      {select(Vec3::Zero(), Vec3::Constant(kSide)), {true, true, true}, Vec3::Zero()},
      {select(Vec3::Constant(1), Vec3::Constant(2)), {true, true, true}, Vec3::Zero()}};
  try {
    Simulation simulation(scene);
    FAIL() << "no error";
  } catch (const SceneError& error) {
    EXPECT_EQ(std::string(error.what()), "constraints[1].where.box: selects no node");
  }
  scene.constraints.clear();
  scene.loads = {{select(Vec3::Constant(0.011), Vec3::Constant(0.019)), Vec3(1, 0, 0)}};
  try {
    Simulation simulation(scene);
    FAIL() << "no error";
  } catch (const SceneError& error) {
    EXPECT_EQ(std::string(error.what()), "loads[0].where.box: selects no node");
  }
}

TEST(Simulation, InvalidSceneIsRejectedBeforeMeshing) {
  Scene scene = free_cube();
  scene.material.youngs_modulus = 0;
  EXPECT_THROW(Simulation{scene}, SceneError);
}

TEST(Simulation, TetsTooSmallToHaveAVolumeAreSceneErrors) {
  Scene scene = free_cube();
  scene.mesh.box.size = Vec3::Constant(1e-120);  // positive, but the volumes underflow to 0
  try {
    Simulation simulation(scene);
    FAIL() << "no error";
  } catch (const SceneError& error) {
    EXPECT_EQ(error.path(), "mesh");
    EXPECT_NE(error.reason().find("non-positive rest volume"), std::string::npos);
  }
}

TEST(Simulation, SameSceneGivesBitwiseSameState) {
  const Scene scene = clamped_cube_under_gravity();
  Simulation first(scene);
  Simulation second(scene);
  for (int step = 0; step < 500; ++step) {
    first.step();
    second.step();
  }
  EXPECT_TRUE((first.mesh().x.array() == second.mesh().x.array()).all());
  EXPECT_TRUE((first.mesh().v.array() == second.mesh().v.array()).all());
}

}  // namespace
}  // namespace incise::sim
