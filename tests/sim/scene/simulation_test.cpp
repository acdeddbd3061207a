#include "sim/scene/simulation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
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

bool same_state(const Simulation& a, const Simulation& b) {
  return (a.mesh().x.array() == b.mesh().x.array()).all() &&
         (a.mesh().v.array() == b.mesh().v.array()).all() && a.steps_taken() == b.steps_taken();
}

// A cube clamped at x = 0 and pulled at x = L over a ramp of 50 steps, under gravity.
Scene ramped_cube() {
  Scene scene = clamped_cube_under_gravity();
  scene.solver.steps = 100;
  scene.constraints = {
      {select(Vec3::Zero(), Vec3(0, kSide, kSide)), {true, true, true}, Vec3::Zero()},
      {select(Vec3(kSide, 0, 0), Vec3::Constant(kSide)), {true, false, false}, Vec3(0.004, 0, 0)}};
  return scene;
}

TEST(Simulation, RestoredStateStepsOnBitForBitLikeTheUninterruptedRun) {
  const Scene scene = ramped_cube();
  // Saved inside the ramp (20), at its end (50) and after it (70); restored into a simulation
  // that has run elsewhere (its ramp further along or not started).
  for (const int saved_at : {0, 20, 50, 70}) {
    Simulation reference(scene);
    for (int step = 0; step < saved_at; ++step)
      reference.step();
    const SimulationState state = reference.save_state();
    EXPECT_EQ(state.steps_taken, saved_at);
    for (const int other_steps : {0, 35, 90}) {
      Simulation restored(scene);
      for (int step = 0; step < other_steps; ++step)
        restored.step();
      const Real* x_data = restored.mesh().x.data();
      restored.restore_state(state);
      EXPECT_EQ(restored.mesh().x.data(), x_data);  // copied into place
      ASSERT_TRUE(same_state(restored, reference));
      EXPECT_TRUE(
          (restored.prescribed().position.array() == reference.prescribed().position.array())
              .all());
      Simulation uninterrupted = reference;
      for (int step = 0; step < 60; ++step) {
        uninterrupted.step();
        restored.step();
        ASSERT_TRUE(same_state(restored, uninterrupted))
            << "saved at " << saved_at << ", other " << other_steps << ", step " << step;
      }
    }
  }
}

TEST(Simulation, RestoreRejectsAStateOfAnotherSizeAndKeepsItsOwn) {
  Simulation simulation(free_cube());
  simulation.step();
  const SimulationState before = simulation.save_state();
  SimulationState wrong = before;
  wrong.positions = Points::Zero(7, 3);
  EXPECT_THROW(simulation.restore_state(wrong), std::invalid_argument);
  wrong = before;
  wrong.velocities = Points::Zero(before.velocities.rows() + 1, 3);
  EXPECT_THROW(simulation.restore_state(wrong), std::invalid_argument);
  wrong = before;
  wrong.steps_taken = -1;
  EXPECT_THROW(simulation.restore_state(wrong), std::invalid_argument);
  EXPECT_TRUE((simulation.mesh().x.array() == before.positions.array()).all());
  EXPECT_EQ(simulation.steps_taken(), 1);
}

TEST(Simulation, AdditionalForcesActForOneStepOnly) {
  Scene scene = free_cube();
  scene.gravity = Vec3(0, 0, -9.81);
  Simulation plain(scene);
  Simulation pushed(scene);
  const int n = plain.mesh().num_nodes();
  // Zero additional forces change nothing, bit for bit.
  for (int step = 0; step < 10; ++step) {
    plain.step();
    pushed.step(Points::Zero(n, 3));
  }
  ASSERT_TRUE(same_state(plain, pushed));
  // A push on one node changes its velocity by dt f / m in that step...
  const int node = n - 1;  // the top corner
  const Vec3 force(0.01, 0, -0.02);
  Points push = Points::Zero(n, 3);
  push.row(node) = force.transpose();
  plain.step();
  pushed.step(push);
  const Vec3 dv = scene.solver.dt * force / pushed.model().masses()(node);
  EXPECT_LT((row3(pushed.mesh().v, node) - row3(plain.mesh().v, node) - dv).norm(),
            1e-12 * dv.norm());
  // ...and then acts no more: internal forces cancel, so the momenta differ by its impulse only.
  for (int step = 0; step < 50; ++step) {
    plain.step();
    pushed.step();
  }
  const VecX& m = plain.model().masses();
  const Vec3 impulse = pushed.mesh().v.transpose() * m - plain.mesh().v.transpose() * m;
  EXPECT_LT((impulse - scene.solver.dt * force).norm(), 1e-9 * scene.solver.dt * force.norm());
  EXPECT_THROW(pushed.step(Points::Zero(n - 1, 3)), std::invalid_argument);
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
