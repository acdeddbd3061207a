#pragma once

#include <cstdint>

#include "sim/core/types.h"
#include "sim/mesh/tet_mesh.h"
#include "sim/models/mass_spring.h"
#include "sim/scene/scene.h"
#include "sim/solve/symplectic_euler.h"

namespace incise::sim {

// A scene made runnable: its mesh, model, boundary conditions and loads, advanced one step at a
// time. Each step:
//   f = loads + model forces(x, v);  prescribed positions for the end of the step;
//   symplectic_euler_step(dt, gravity, 1 / m, prescribed, f, x, v).
// A "displace" constraint's displacement is ramped linearly over the first max(1, steps / 2) of
// the scene's solver.steps (step n, counted from 0, ends at (n + 1) / ramp of it) and then held;
// "fix" holds the rest coordinate throughout. Single-threaded and deterministic: the same scene
// gives the same states bit for bit. No allocation per step.
class Simulation {
 public:
  // Throws SceneError for an invalid scene (validate_scene) or a selection that picks no node.
  explicit Simulation(const Scene& scene);

  void step();

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
