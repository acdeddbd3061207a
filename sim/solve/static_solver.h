#pragma once
// Static equilibrium: find x with
//   r(x) = f_internal(x, 0) + f_external + M g = 0 on the free coordinates,
// the prescribed coordinates held at their values. Newton's method: with K = -dr/dx (model.h),
// each iteration solves K dx = r (CG or LDLT through ConstrainedSystem, the inner tolerance
// tightened with the residual, eta = min(0.01, relative residual), so that convergence stays
// quadratic near the solution; Eisenstat and Walker, SIAM J. Sci. Comput. 17, 1996) and
// backtracks dx by halving until the residual norm decreases (Armijo: ||r(x + s dx)|| <=
// (1 - 1e-4 s) ||r(x)||; Dennis and Schnabel 1983, 6.3) or the total potential
//   Phi(x) = E(x) - (f_external + M g) . x,   grad Phi = -r,
// does (Armijo on Phi: Phi(x + s dx) <= Phi(x) + 1e-4 s grad Phi . dx). The second test keeps
// Newton going where the tangent is only approximate (the QR corotational K omits the change of
// R; a positive definite approximation still gives a descent direction of Phi, where the residual
// norm may first grow); the first one decides near the solution, where differences of Phi drown
// in round-off.
// Relative residual: ||r_free|| / scale, scale = the largest of ||f_external + M g||, the norm of
// the reactions (internal forces on the held coordinates) and the first iteration's ||r_free||;
// so a loaded, a displacement-driven and an already balanced problem all have a meaningful
// measure.

#include <vector>

#include "sim/core/types.h"
#include "sim/models/model.h"
#include "sim/solve/constrained_system.h"
#include "sim/solve/symplectic_euler.h"

namespace incise::sim {

struct StaticSettings {
  Real tolerance = 1e-8;     // converged when the relative residual is <= tolerance
  int max_iterations = 50;   // Newton iterations, >= 0
  int max_line_search = 30;  // halvings per iteration, >= 0
  LinearSolveSettings linear{LinearSolver::matrix_free_cg, Preconditioner::jacobi,
                             CgSettings{1e-2, 2000}};  // cg.tolerance is the loosest inner one
};

struct StaticReport {
  int iterations = 0;               // Newton iterations taken
  int linear_iterations = 0;        // CG iterations, all Newton iterations together
  Real relative_residual = 0;       // at the returned x
  bool converged = false;           // relative_residual <= tolerance
  bool finite = true;               // false: non-finite forces or a failed factorisation stopped it
  bool line_search_failed = false;  // no decrease found within max_line_search halvings
  std::vector<Real> residual_history;  // relative residual before each iteration and at the end
};

class StaticSolver {
 public:
  // Throws std::invalid_argument for settings out of range.
  explicit StaticSolver(StaticSettings settings = {});

  // Solves for x in place, starting from x (prescribed coordinates first set to their values).
  // gravity [m/s^2]; external_forces #nodes by 3 [N] (empty for none). Returns after
  // convergence, max_iterations, a failed line search or a non-finite evaluation; x is then the
  // last accepted iterate (always finite). Allocates (the history; work arrays on first use).
  // Throws std::invalid_argument for arrays of the wrong size.
  StaticReport solve(const Vec3& gravity, const Points& external_forces,
                     const Prescribed& prescribed, Model& model, Points& x);

  const StaticSettings& settings() const { return settings_; }

 private:
  // r = f_internal(x, 0) + load; returns ||r|| over free coordinates, the reactions' norm in
  // reaction_norm (NaN if not finite).
  Real residual(Model& model, const Points& x, Points& r, Real& reaction_norm);
  // Phi(x) = E(x) - load . x.
  Real potential(const Model& model, const Points& x) const;

  StaticSettings settings_;
  ConstrainedSystem system_;
  Points free_, load_, zero_velocity_, r_, dx_, x_trial_;
};

}  // namespace incise::sim
