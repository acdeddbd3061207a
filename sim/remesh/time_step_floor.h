#pragma once

// The time-step floor of Paloc 2006 ("Minimum time step"): a mesh with no element shorter than
// l_min never needs an explicit step below dt_min = safety * l_min / c, with c the fastest wave
// speed (p_wave_speed). A scene gives either l_min or dt_min; these convert one into the other with
// the same formula and safety factor as sim/solve/stable_time_step.h (time_step_floor and
// length_floor there take the material instead of c), so the two agree exactly.
// Which length: stable_time_step measures the smallest altitude, never longer than the smallest
// edge. Refinement's floor is on edges (RefinementSettings::l_min); only with floor_altitudes on
// does it also hold for the altitudes of the tets refinement creates.

#include "sim/core/types.h"
#include "sim/solve/stable_time_step.h"

namespace incise::sim::remesh {

// l_min = dt_min c / safety [m]. Throws std::invalid_argument unless dt_min > 0, c > 0 and
// 0 < safety <= 1.
Real l_min_for_dt_min(Real dt_min, Real wave_speed, Real safety = kExplicitSafety);

// dt_min = safety l_min / c [s]. Throws std::invalid_argument unless l_min > 0, c > 0 and
// 0 < safety <= 1.
Real dt_min_for_l_min(Real l_min, Real wave_speed, Real safety = kExplicitSafety);

}  // namespace incise::sim::remesh
