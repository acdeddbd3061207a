#pragma once
// The explicit stability limit from the mesh: the Courant-Friedrichs-Lewy condition
// dt_c = l_min / c (Paloc 2006, "Minimum time step"), with c the fastest wave speed of the
// material and l_min the shortest length an element offers.

#include "sim/core/types.h"
#include "sim/mesh/tet_mesh.h"

namespace incise::sim {

// Shortest lengths over a set of tets.
struct ElementLengths {
  Real min_edge = 0;      // shortest tet edge [m]
  Real min_altitude = 0;  // shortest distance from a tet's vertex to its opposite face [m]
};

// Safety factor on l_min / c. For a linear tet with lumped mass the highest element frequency is
// not exactly 2 c / l for any single length l. With l the smallest altitude (never longer than
// the smallest edge) we measured l_min / c against the exact limit 2 / omega_max (omega_max^2 the
// largest eigenvalue of M^-1 K, by power iteration) on box meshes (tests/sim/solve/
// stable_time_step_test.cpp): l_min / c = 1.03, 1.04, 1.07, 1.08 times the exact limit for
// nu = 0, 0.3, 0.45, 0.49, i.e. slightly unstable on its own. 0.5 puts the estimate at about half
// the limit: margin for distorted meshes (slivers), nonlinear stiffening under compression and
// damping, which all lower the limit.
inline constexpr Real kExplicitSafety = 0.5;

// The shortest edge and altitude of tets over points. Allocates nothing.
//   points  #nodes by 3 positions [m]
//   tets    #tets by 4 node indices
// Throws std::invalid_argument if there is no tet or a tet has (near) zero volume (an altitude
// of zero would make every step unstable).
ElementLengths element_lengths(const Points& points, const Tets& tets);

// P-wave (dilatational) speed c = sqrt(E (1 - nu) / (rho (1 + nu) (1 - 2 nu))) [m/s], the
// fastest wave in an isotropic linear solid; it grows without bound as nu -> 0.5.
// Throws std::invalid_argument unless E > 0, -1 < nu < 0.5 and density > 0.
Real p_wave_speed(Real youngs_modulus, Real poisson_ratio, Real density);

// dt = safety * l_min / c with l_min the smallest altitude of the mesh at its current positions
// mesh.x [s]. Throws as element_lengths and p_wave_speed, or for safety outside (0, 1].
Real stable_time_step(const TetMesh& mesh, Real youngs_modulus, Real poisson_ratio, Real density,
                      Real safety = kExplicitSafety);

// The floor of Paloc 2006: a mesh whose elements stay at least l_floor long never needs a step
// below dt_min = safety * l_floor / c [s]. Remeshing keeps l_min >= l_floor so that an adaptive
// step floored at dt_min stays stable. Throws as p_wave_speed, or for l_floor <= 0.
Real time_step_floor(Real l_floor, Real youngs_modulus, Real poisson_ratio, Real density,
                     Real safety = kExplicitSafety);

// The inverse: the smallest element length l_floor = dt_min c / safety [m] that keeps the stable
// step at or above dt_min. Throws as p_wave_speed, or for dt_min <= 0.
Real length_floor(Real dt_min, Real youngs_modulus, Real poisson_ratio, Real density,
                  Real safety = kExplicitSafety);

}  // namespace incise::sim
