#pragma once
// The searches of calibration (docs/calibration.md), each minimising a misfit ||r(z)||^2 over a
// box of z, each with a budget of evaluations, a progress report per generation or iteration and
// a cancel flag, so that none runs forever:
//   ga      seed 004's genetic algorithm, the baseline: real-coded, tournament selection, blend
//           crossover (BLX-alpha), Gaussian mutation, the best two kept (elitism)
//   cmaes   CMA-ES (Hansen, "The CMA Evolution Strategy: A Tutorial", 2016): weighted
//           recombination, cumulative step-size adaptation, rank-one and rank-mu updates
//   lm      Levenberg-Marquardt on the residuals, the Jacobian by forward differences, the
//           damping scaled by the diagonal of J^T J (Marquardt 1963)
// All are deterministic for a seed (lm uses none). The misfit they report never increases from
// one generation or iteration to the next: ga keeps its best, cmaes reports the best so far, lm
// accepts a step only when it lowers the misfit.

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sim/core/types.h"

namespace incise::sim::calibrate {

enum class Method { ga, cmaes, lm };

// "ga", "cmaes", "lm"
std::optional<Method> method_named(std::string_view name);
std::string_view method_name(Method method);

struct Problem {
  VecX start, lower, upper;  // the first point and the box (lower < upper)
  // The residuals r at z (always the same size); false when z cannot be evaluated (its misfit is
  // then taken as infinite).
  std::function<bool(const VecX& z, VecX& r)> residuals;
};

struct Progress {
  int iteration = 0;    // generation (ga, cmaes) or iteration (lm), from 1
  int evaluations = 0;  // so far
  Real misfit = 0;      // the best so far
  VecX best;            // its point
};

struct OptimiserSettings {
  Method method = Method::lm;
  int max_evaluations = 2000;  // the budget, >= 1: no search evaluates more
  std::uint64_t seed = 1;      // ga, cmaes
  int population = 0;          // ga, cmaes; 0 = the method's default (ga 40, cmaes 4 + 3 ln n)
  Real initial_step = 0.3;     // ga's initial spread, cmaes's sigma, in z (0.3: a factor 1.35)
  Real tolerance = 1e-10;      // lm: stop when an iteration lowers the misfit by less, relatively
  const std::atomic<bool>* cancel = nullptr;      // stop soon after it becomes true
  std::function<void(const Progress&)> progress;  // after each generation or iteration
};

struct OptimiserResult {
  VecX best;              // the lowest misfit's point
  Real misfit = 0;        // ||r(best)||^2
  Real start_misfit = 0;  // ||r(start)||^2
  int evaluations = 0;
  int iterations = 0;
  std::vector<Real> history;  // the best misfit after each generation or iteration
  // The spread of each coordinate in z at the end: ga the standard deviation over its better
  // half, cmaes sigma sqrt(C_ii), lm the standard error sqrt(s^2 (J^T J)^-1_ii).
  VecX spread;
  std::string stopped;  // why it stopped: "budget", "converged", "cancelled", ...
};

// Throws std::invalid_argument for a budget below 1, mismatched sizes or an empty box.
OptimiserResult minimise(const Problem& problem, const OptimiserSettings& settings);

}  // namespace incise::sim::calibrate
