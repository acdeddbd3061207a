#pragma once
// Explicit central differences with lumped mass (Paloc 2006, "Volumetric nonlinear FEM": the
// explicit operator of nonlinear dynamic analysis), in its velocity form with velocities at full
// steps (Verlet / leapfrog, Hairer, Lubich, Wanner 2003, eq. I.1.17):
//   v_half = v_n + h/2 a(x_n, v_n)
//   x_n+1  = x_n + h v_half
//   v_n+1  = v_half + h/2 a(x_n+1, v_half)
//   a(x, v) = M^-1 (f_internal(x, v) + f_external) + g
// Eliminating v gives x_n+1 - 2 x_n + x_n-1 = h^2 a_n, the central difference of x'' = a. The
// damping forces use the latest explicit velocity (v_half at the end of the step). One force
// evaluation per step: the end-of-step forces are kept for the next step's first half, unless x
// or v were changed in between (compared with the state the last step left), in which case they
// are evaluated afresh. Stable for h < 2 / omega_max (stable_time_step estimates it from the
// mesh); for the harmonic oscillator x_n = A cos(n theta) with cos theta = 1 - (omega h)^2 / 2.
// Prescribed coordinates: x_n+1 = position, v = (position - x_n) / h. Nodes without mass move
// with their velocity unaccelerated.

#include "sim/core/types.h"
#include "sim/models/model.h"
#include "sim/solve/explicit_report.h"
#include "sim/solve/symplectic_euler.h"

namespace incise::sim {

class CentralDifference {
 public:
  // One step of h [s] (> 0). gravity [m/s^2]; external_forces #nodes by 3 [N] (empty for none),
  // held over the step. If the new state is not finite, x and v are restored to the state at the
  // start and the report says finite = false (the caller should reduce h or stop).
  // Allocates nothing after the first step. Throws std::invalid_argument for h <= 0 or arrays
  // of the wrong size.
  ExplicitReport step(Real h, const Vec3& gravity, const Points& external_forces,
                      const Prescribed& prescribed, Model& model, Points& x, Points& v);

  // Drops the kept forces (e.g. after the model's parameters changed).
  void reset() { has_force_ = false; }

 private:
  void half_kick(Real h, const Vec3& gravity, const Points& external_forces, const VecX& m,
                 Points& v) const;

  Points force_;          // internal forces at (x_end_, v_half of the last step)
  Points x_end_, v_end_;  // the state the last step left (also the restore point)
  bool has_force_ = false;
};

}  // namespace incise::sim
