#pragma once

#include "sim/core/types.h"

namespace incise::sim {

// Coordinates held at given values instead of integrated (Dirichlet conditions), per axis.
struct Prescribed {
  AxisMask mask;    // #nodes by 3, 1 where the coordinate is prescribed; empty = none
  Points position;  // #nodes by 3 prescribed positions [m] for the end of the step, read where
                    // mask is 1
};

// One step of symplectic (semi-implicit) Euler: the velocity is updated first and the position
// with the new velocity (Hairer, Lubich, Wanner, "Geometric Numerical Integration", eq. I.1.9),
// which keeps the energy of an undamped oscillator bounded for dt below the stability limit.
// Per free coordinate:
//   v <- v + dt (f inv_mass + g),  x <- x + dt v
// A node with inv_mass 0 is fixed: forces and gravity do not act on it (its v stays as it is).
// A prescribed coordinate is moved onto its value: x <- position, v <- (position - x_old) / dt,
// so that the dampers see a moving constraint's velocity.
//   dt        time step [s], > 0
//   gravity   acceleration g [m/s^2]
//   inv_mass  #nodes 1 / m_i [1/kg], 0 for fixed nodes
//   f         #nodes by 3 total forces [N] (internal + external, without gravity)
//   x, v      #nodes by 3 positions [m] and velocities [m/s], advanced in place
// Allocates nothing.
void symplectic_euler_step(Real dt, const Vec3& gravity, const VecX& inv_mass,
                           const Prescribed& prescribed, const Points& f, Points& x, Points& v);

}  // namespace incise::sim
