#pragma once
// Preconditioned conjugate gradients (Hestenes and Stiefel 1952; Shewchuk, "An Introduction to the
// Conjugate Gradient Method Without the Agonizing Pain", 1994, B3) on #nodes by 3 arrays, for the
// symmetric positive definite systems of the implicit and static solvers. Warm-started from the
// given solution, capped in iterations, and it stops rather than divide by a non-positive
// curvature p^T A p (an indefinite tangent stiffness).

#include <cmath>

#include "sim/core/types.h"

namespace incise::sim {

struct CgSettings {
  Real tolerance = 1e-8;     // stop when ||b - A y|| <= tolerance ||b||
  int max_iterations = 500;  // cap, >= 0
};

struct CgReport {
  int iterations = 0;
  Real relative_residual = 0;  // ||b - A y|| / ||b|| at the end (0 for b = 0)
  bool converged = false;      // relative_residual <= tolerance
  bool breakdown = false;      // stopped at p^T A p <= 0 or a non-finite value
};

// The four work arrays of conjugate_gradient, sized once.
struct CgWorkspace {
  Points r, z, p, q;
  void resize(Eigen::Index num_nodes) {
    if (r.rows() == num_nodes) return;
    r.resize(num_nodes, 3);
    z.resize(num_nodes, 3);
    p.resize(num_nodes, 3);
    q.resize(num_nodes, 3);
  }
};

// Solves A y = b. y holds the initial guess on entry and the solution on return.
//   apply(p, q)           writes q = A p (both #nodes by 3)
//   precondition(r, z)    writes z = P^-1 r with P symmetric positive definite
// A must be symmetric; constraints are the caller's: a b, y, apply and precondition that keep the
// held coordinates at zero keep the iteration in the free subspace. Allocates nothing once work is
// sized (work.resize(#nodes)).
template <class Apply, class Precondition>
CgReport conjugate_gradient(const Apply& apply, const Precondition& precondition, const Points& b,
                            const CgSettings& settings, CgWorkspace& work, Points& y) {
  CgReport report;
  const Real b_norm = b.norm();
  if (b_norm == 0) {
    y.setZero();
    report.converged = true;
    return report;
  }
  const Real goal = settings.tolerance * b_norm;
  apply(y, work.q);
  work.r = b - work.q;
  Real r_norm = work.r.norm();
  if (!std::isfinite(r_norm)) {  // a non-finite warm start: begin from zero instead
    y.setZero();
    work.r = b;
    r_norm = b_norm;
  }
  Real rz_old = 0;
  while (r_norm > goal && report.iterations < settings.max_iterations) {
    precondition(work.r, work.z);
    const Real rz = work.r.cwiseProduct(work.z).sum();
    if (report.iterations == 0) {
      work.p = work.z;
    } else {
      work.p = work.z + (rz / rz_old) * work.p;
    }
    apply(work.p, work.q);
    const Real curvature = work.p.cwiseProduct(work.q).sum();
    if (!(curvature > 0) || !std::isfinite(rz)) {
      report.breakdown = true;
      break;
    }
    const Real alpha = rz / curvature;
    y += alpha * work.p;
    work.r -= alpha * work.q;
    r_norm = work.r.norm();
    rz_old = rz;
    ++report.iterations;
  }
  report.relative_residual = r_norm / b_norm;
  report.converged = r_norm <= goal;
  return report;
}

}  // namespace incise::sim
