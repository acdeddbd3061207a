#include "sim/solve/static_solver.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "sim/solve/free_coordinates.h"

namespace incise::sim {

StaticSolver::StaticSolver(StaticSettings settings) : settings_(settings) {
  if (!(settings_.tolerance > 0) || settings_.max_iterations < 0 || settings_.max_line_search < 0 ||
      !(settings_.linear.cg.tolerance > 0) || settings_.linear.cg.max_iterations < 0) {
    throw std::invalid_argument(
        "static solver needs tolerances > 0 and non-negative iteration caps");
  }
}

Real StaticSolver::residual(Model& model, const Points& x, Points& r, Real& reaction_norm) {
  r = load_;
  model.add_forces(x, zero_velocity_, r);
  if (!all_finite(r)) {
    reaction_norm = std::numeric_limits<Real>::quiet_NaN();
    return std::numeric_limits<Real>::quiet_NaN();
  }
  // Reactions: what the held coordinates must supply, i.e. r there (the load on them is
  // carried by the support as well).
  reaction_norm = (r - r.cwiseProduct(free_)).norm();
  return r.cwiseProduct(free_).norm();
}

Real StaticSolver::potential(const Model& model, const Points& x) const {
  return model.potential_energy(x) - load_.cwiseProduct(x).sum();
}

StaticReport StaticSolver::solve(const Vec3& gravity, const Points& external_forces,
                                 const Prescribed& prescribed, Model& model, Points& x) {
  const VecX& m = model.masses();
  const Eigen::Index n = m.size();
  if (x.rows() != n || (external_forces.rows() != 0 && external_forces.rows() != n)) {
    throw std::invalid_argument("static solver: x and external forces must be #nodes by 3");
  }
  check_prescribed(prescribed, static_cast<int>(n));
  if (load_.rows() != n) {
    for (Points* p : {&load_, &zero_velocity_, &r_, &dx_, &x_trial_})
      p->resize(n, 3);
  }
  zero_velocity_.setZero();
  free_coordinates(prescribed, m, free_);
  for (Eigen::Index i = 0; i < n; ++i)
    load_.row(i) = m(i) * gravity.transpose();
  if (external_forces.rows() != 0) load_ += external_forces;
  for (Eigen::Index i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      if (is_prescribed(prescribed, i, a)) x(i, a) = prescribed.position(i, a);
    }
  }

  StaticReport report;
  const Real load_norm = load_.norm();
  Real reaction_norm = 0;
  Real r_norm = residual(model, x, r_, reaction_norm);
  if (!std::isfinite(r_norm)) {
    report.finite = false;
    report.relative_residual = std::numeric_limits<Real>::infinity();
    return report;
  }
  const Real initial_norm = r_norm;
  auto relative = [&](Real norm, Real reactions) {
    const Real scale = std::max({load_norm, reactions, initial_norm});
    return scale > 0 ? norm / scale : Real(0);
  };
  report.relative_residual = relative(r_norm, reaction_norm);
  report.residual_history.push_back(report.relative_residual);
  dx_.setZero();

  while (report.relative_residual > settings_.tolerance &&
         report.iterations < settings_.max_iterations) {
    model.prepare_stiffness(x);
    LinearSolveSettings linear = settings_.linear;
    linear.cg.tolerance =
        std::max(std::min(linear.cg.tolerance, report.relative_residual), Real(1e-14));
    if (!system_.prepare(model, 0, 0, 1, free_, linear)) {
      report.finite = false;
      break;
    }
    dx_.setZero();  // Newton steps change direction; no warm start
    const CgReport cg = system_.solve(r_, dx_);
    report.linear_iterations += cg.iterations;
    ++report.iterations;
    if (!all_finite(dx_)) {
      report.finite = false;
      break;
    }
    // Backtracking: a step is taken when it decreases the residual norm or the total potential
    // (static_solver.h); the potential is evaluated only when the residual test fails.
    const Real slope = -r_.cwiseProduct(free_).cwiseProduct(dx_).sum();  // grad Phi . dx
    Real potential_here = std::numeric_limits<Real>::quiet_NaN();
    Real step = 1;
    Real trial_norm = 0, trial_reactions = 0;
    bool decreased = false;
    for (int halving = 0; halving <= settings_.max_line_search; ++halving) {
      x_trial_ = x + step * dx_;
      trial_norm = residual(model, x_trial_, r_, trial_reactions);
      if (std::isfinite(trial_norm) && trial_norm <= (1 - 1e-4 * step) * r_norm) {
        decreased = true;
        break;
      }
      if (std::isfinite(trial_norm) && slope < 0) {
        if (std::isnan(potential_here)) potential_here = potential(model, x);
        if (potential(model, x_trial_) <= potential_here + 1e-4 * step * slope) {
          decreased = true;
          break;
        }
      }
      step /= 2;
    }
    if (!decreased) {
      report.line_search_failed = true;
      residual(model, x, r_, reaction_norm);  // r_ back to the accepted iterate
      break;
    }
    x = x_trial_;
    r_norm = trial_norm;
    reaction_norm = trial_reactions;
    report.relative_residual = relative(r_norm, reaction_norm);
    report.residual_history.push_back(report.relative_residual);
  }
  report.converged = report.finite && report.relative_residual <= settings_.tolerance;
  return report;
}

}  // namespace incise::sim
