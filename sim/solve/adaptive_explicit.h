#pragma once
// Adaptive explicit integration with an embedded error estimate (Paloc 2006, "Adaptive time step"
// and "Minimum time step"): the Bogacki-Shampine 3(2) pair (Bogacki and Shampine, Appl. Math.
// Lett. 2(4), 1989) on the first-order system y = (x, v), y' = (v, a(x, v)),
//   a(x, v) = M^-1 (f_internal(x, v) + f_external) + g.
// The third-order solution is kept; the difference to the embedded second-order one estimates the
// local error. Error norm: the largest of |e_x| / position_tolerance and |e_v| /
// velocity_tolerance over all coordinates; a step is accepted when it is <= 1. The next step is
// h * clamp(0.9 err^(-1/3), 0.2, 5) (Hairer, Norsett, Wanner I, II.4), within [dt_min, dt_max].
// A step that fails at dt_min is accepted anyway and counted as clamped: the floor guarantees the
// frame rate (Paloc 2006 keeps dt_min stable by keeping elements longer than l_floor, see
// stable_time_step.h). First same as last: the last stage of an accepted step is the first of the
// next, so an accepted step costs 3 force evaluations.

#include "sim/core/types.h"
#include "sim/models/model.h"
#include "sim/solve/explicit_report.h"
#include "sim/solve/symplectic_euler.h"

namespace incise::sim {

struct AdaptiveExplicitSettings {
  Real position_tolerance = 1e-6;  // local error allowed per step in a position [m], > 0
  Real velocity_tolerance = 1e-4;  // ... in a velocity [m/s], > 0
  Real dt_initial = 1e-4;          // first step tried [s]
  Real dt_min = 1e-7;              // floor [s], 0 < dt_min <= dt_initial <= dt_max
  Real dt_max = 1e-2;              // ceiling [s]
  int max_steps = 1000000;         // cap on steps (accepted + rejected) per advance call
};

class AdaptiveExplicit {
 public:
  // Throws std::invalid_argument for settings out of range.
  explicit AdaptiveExplicit(AdaptiveExplicitSettings settings);

  // Advances x, v by duration [s] (> 0) in as many steps as the error needs, the last one cut to
  // end exactly at duration. gravity [m/s^2]; external_forces #nodes by 3 [N] (empty for none),
  // held over the call. Prescribed coordinates move linearly from their start to position over
  // the call and end on it exactly. If a step at dt_min gives a non-finite state, x and v keep the
  // last finite state and the report says finite = false. Allocates nothing after the first call.
  // Throws std::invalid_argument for duration <= 0 or arrays of the wrong size.
  ExplicitReport advance(Real duration, const Vec3& gravity, const Points& external_forces,
                         const Prescribed& prescribed, Model& model, Points& x, Points& v);

  // The step the controller will try next [s].
  Real next_dt() const { return dt_; }
  const AdaptiveExplicitSettings& settings() const { return settings_; }

 private:
  // k_x = v (held: their velocity), k_v = a(x, v) (0 where held or massless).
  void derivative(Model& model, const Points& x, const Points& v, Points& kx, Points& kv);

  AdaptiveExplicitSettings settings_;
  Real dt_;
  const Vec3* gravity_ = nullptr;
  const Points* external_ = nullptr;
  Points free_, held_velocity_, force_;
  Points kx_[4], kv_[4];
  Points x_stage_, v_stage_, x_new_, v_new_;
};

}  // namespace incise::sim
