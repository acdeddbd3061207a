#pragma once
// Linearised backward Euler (Baraff and Witkin, "Large Steps in Cloth Simulation", SIGGRAPH 1998,
// eq. 6; Physically Realistic FEM, section 2.3). Backward Euler on M v' = f(x, v):
//   M (v1 - v0) = h f(x1, v1),   x1 = x0 + h v1.
// One Newton step from (x0, v0), with K = -df/dx and D = -df/dv (model.h) and dv = v1 - v0:
//   f(x1, v1) ~ f0 - K (x1 - x0) - D dv = f0 - h K (v0 + dv) - D dv,
// hence
//   (M + h D + h^2 K) dv = h (f0 - h K v0),   f0 = f_internal(x0, v0) + f_external + M g.
// The system is symmetric positive definite for a stable linearisation, solved by CG (matrix-free
// or assembled) or LDLT (ConstrainedSystem). Unconditionally stable for the linear undamped
// oscillator: each step multiplies the amplitude by 1 / sqrt(1 + (omega h)^2), i.e. the energy by
// 1 / (1 + (omega h)^2), its numerical damping.
// Prescribed coordinates end the step on their values, x1 = position, with
// v1 = (position - x0) / h; their known dv moves to the right-hand side. Nodes without mass keep
// their velocity.

#include "sim/core/types.h"
#include "sim/models/model.h"
#include "sim/solve/constrained_system.h"
#include "sim/solve/symplectic_euler.h"

namespace incise::sim {

struct ImplicitEulerSettings {
  LinearSolveSettings linear{LinearSolver::matrix_free_cg, Preconditioner::jacobi,
                             CgSettings{1e-6, 200}};
  bool warm_start = true;  // start CG from the previous step's dv
};

struct ImplicitStepReport {
  int iterations = 0;          // CG iterations of the step
  Real relative_residual = 0;  // ||rhs - A dv|| / ||rhs|| on the free coordinates
  bool converged = false;      // relative_residual <= the CG tolerance
  bool finite = true;  // false: forces, matrix or solution not finite, or LDLT failed; x and v
                       // are then left as they were
};

class ImplicitEuler {
 public:
  // Throws std::invalid_argument for a tolerance <= 0 or max_iterations < 0.
  explicit ImplicitEuler(ImplicitEulerSettings settings = {});

  // Advances x, v by one step of h [s] (> 0). gravity [m/s^2]; external_forces #nodes by 3 [N]
  // (or empty for none); prescribed as in symplectic_euler.h. Calls model.prepare_stiffness(x0).
  // Allocates nothing after the first step, except inside Eigen's LDLT and when the node count or
  // the stiffness pattern changes. Throws std::invalid_argument for h <= 0 or arrays of the wrong
  // size.
  ImplicitStepReport step(Real h, const Vec3& gravity, const Points& external_forces,
                          const Prescribed& prescribed, Model& model, Points& x, Points& v);

  // Forgets the warm start (after a topology change or a restored state).
  void reset() { has_last_dv_ = false; }

  const ImplicitEulerSettings& settings() const { return settings_; }
  // The linear system of the last step (its matrix, pattern and preconditioner statistics).
  const ConstrainedSystem& system() const { return system_; }

 private:
  ImplicitEulerSettings settings_;
  ConstrainedSystem system_;
  Points free_, force_, rhs_, work_, dv_, held_dv_, last_dv_;
  bool has_last_dv_ = false;
};

}  // namespace incise::sim
