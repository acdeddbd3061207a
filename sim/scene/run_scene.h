#pragma once

#include <cstdint>
#include <string>

#include "sim/core/types.h"
#include "sim/scene/scene.h"

namespace incise::sim {

// The outcome of running a scene to its end (the fields of `incise solve`'s RESULT.json).
struct RunResult {
  Points rest;          // #nodes by 3 rest positions [m]
  Points displacement;  // #nodes by 3 final x - rest [m]
  int num_tets = 0;
  std::int64_t steps = 0;  // steps taken; fewer than solver.steps if the state blew up
  double ms_per_step = 0;  // median wall time of one step [ms]
  Real max_speed = 0;      // largest node speed at the end [m/s]
  bool finite = true;      // false if the run stopped on a non-finite or diverged state
  // "completed", or one line saying why the run stopped (scene_run.h: not finite, diverged) and
  // at which step.
  std::string status = "completed";
  // Iterative solvers (implicit_euler, static, adaptive_explicit; scene_run.h): whether every
  // solve met solver.tolerance, the iterations (CG, Newton or adaptive steps) in all, and the
  // worst relative residual. Direct steps leave the defaults.
  bool converged = true;
  std::int64_t iterations = 0;
  double relative_residual = 0;
  int inverted_elements = 0;  // at the end (models that report it)
  Points final_positions;     // #nodes by 3 x at the end [m] (= rest + displacement)
};

// The runners (scene_run.h, remesh/adaptive_run.h) time at most this many steps, evenly spaced,
// so that the record stays small for long runs; ms_per_step is their median.
inline constexpr std::int64_t kMaxTimedSteps = 1'000'000;

}  // namespace incise::sim
