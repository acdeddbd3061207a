#pragma once

#include "sim/core/types.h"

namespace incise::sim {

// What an explicit integrator did in one call (CentralDifference::step, AdaptiveExplicit::advance).
struct ExplicitReport {
  int steps = 0;            // accepted steps
  int rejected_steps = 0;   // steps tried and thrown away (error estimate above tolerance)
  int clamped_steps = 0;    // accepted at the floor dt_min although the error was above tolerance
  Real dt_used = 0;         // the last accepted step [s]
  Real min_dt_used = 0;     // the smallest accepted step [s]
  Real error_estimate = 0;  // largest normalised local error of the accepted steps (1 = tolerance;
                            // 0 where there is no estimate, as for central differences)
  bool finite = true;       // false: the state became non-finite (blown up); x and v hold the
                            // last finite state and the call stopped there
  bool completed = true;    // false: stopped before the end (blown up, or the step cap)
};

}  // namespace incise::sim
