#pragma once

#include <cstdint>

#include "sim/core/types.h"
#include "sim/mesh/tet_mesh.h"
#include "sim/models/mass_spring.h"
#include "sim/scene/scene.h"
#include "sim/solve/symplectic_euler.h"

namespace incise::sim {

// The state that evolves while a simulation runs; everything else follows from the scene.
struct SimulationState {
  Points positions;   // #nodes by 3 [m]
  Points velocities;  // #nodes by 3 [m/s]
  std::int64_t steps_taken = 0;
};

// A scene made runnable: its mesh, model, boundary conditions and loads, advanced one step at a
// time. Each step:
//   f = loads + model forces(x, v);  prescribed positions for the end of the step;
//   symplectic_euler_step(dt, gravity, 1 / m, prescribed, f, x, v).
// A "displace" constraint's displacement is ramped linearly over the first max(1, steps / 2) of
// the scene's solver.steps (step n, counted from 0, ends at (n + 1) / ramp of it) and then held;
// "fix" holds the rest coordinate throughout. Single-threaded and deterministic: the same scene
// gives the same states bit for bit, also across save_state / restore_state. No allocation per
// step.
class Simulation {
 public:
  // Throws SceneError for an invalid scene (validate_scene) or a selection that picks no node.
  explicit Simulation(const Scene& scene);

  void step();
  // The same with additional_forces (#nodes by 3 [N], e.g. tool contact) added to the loads for
  // this step only. step(zero forces) gives the same state as step(), bit for bit.
  // Throws std::invalid_argument if additional_forces is not #nodes by 3.
  void step(const Points& additional_forces);

  // A copy of the evolving state (allocates). Restoring it into a Simulation of the same scene and
  // stepping on reproduces the states of the uninterrupted run bit for bit, including where a
  // "displace" ramp stands (it follows steps_taken).
  SimulationState save_state() const;
  // Throws std::invalid_argument if the arrays are not #nodes by 3 or steps_taken < 0; the
  // simulation is unchanged then. Allocates nothing.
  void restore_state(const SimulationState& state);

  const TetMesh& mesh() const { return mesh_; }
  const MassSpring& model() const { return model_; }
  const Prescribed& prescribed() const { return prescribed_; }
  const Points& external_forces() const { return external_forces_; }  // #nodes by 3 loads [N]
  std::int64_t steps_taken() const { return steps_taken_; }
  Real time() const { return static_cast<Real>(steps_taken_) * dt_; }  // [s]

  // Largest node speed [m/s]; NaN if a velocity is not finite.
  Real max_speed() const;
  // Whether every position and velocity is finite.
  bool state_finite() const;
  // The model's forces at the current state, #nodes by 3 [N] (e.g. to read reactions at
  // prescribed nodes). Allocates.
  Points internal_forces() const;

 private:
  void update_prescribed_positions();
  void advance();

  TetMesh mesh_;
  MassSpring model_;
  VecX inv_mass_;
  Prescribed prescribed_;
  Points prescribed_displacement_;  // #nodes by 3 full displacement of prescribed coordinates [m]
  bool ramping_ = false;            // some prescribed displacement is non-zero
  Points external_forces_;
  Points forces_;  // per-step work array
  Vec3 gravity_;
  Real dt_;
  std::int64_t ramp_steps_;
  std::int64_t steps_taken_ = 0;
};

}  // namespace incise::sim
