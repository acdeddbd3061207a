#include "sim/solve/implicit_euler.h"

#include <stdexcept>

#include "sim/solve/free_coordinates.h"

namespace incise::sim {

ImplicitEuler::ImplicitEuler(ImplicitEulerSettings settings) : settings_(settings) {
  if (!(settings_.linear.cg.tolerance > 0) || settings_.linear.cg.max_iterations < 0) {
    throw std::invalid_argument("implicit Euler needs a CG tolerance > 0 and max_iterations >= 0");
  }
}

ImplicitStepReport ImplicitEuler::step(Real h, const Vec3& gravity, const Points& external_forces,
                                       const Prescribed& prescribed, Model& model, Points& x,
                                       Points& v) {
  const VecX& m = model.masses();
  const Eigen::Index n = m.size();
  if (!(h > 0)) throw std::invalid_argument("implicit Euler step needs h > 0");
  if (x.rows() != n || v.rows() != n ||
      (external_forces.rows() != 0 && external_forces.rows() != n)) {
    throw std::invalid_argument("implicit Euler: x, v and external forces must be #nodes by 3");
  }
  check_prescribed(prescribed, static_cast<int>(n));
  if (force_.rows() != n) {
    for (Points* p : {&force_, &rhs_, &work_, &dv_, &held_dv_, &last_dv_})
      p->resize(n, 3);
    has_last_dv_ = false;
  }
  ImplicitStepReport report;
  free_coordinates(prescribed, m, free_);

  // f0 = f_internal(x0, v0) + f_external + M g
  force_.setZero();
  model.add_forces(x, v, force_);
  if (external_forces.rows() != 0) force_ += external_forces;
  for (Eigen::Index i = 0; i < n; ++i)
    force_.row(i) += m(i) * gravity.transpose();
  if (!all_finite(force_)) {
    report.finite = false;
    return report;
  }
  model.prepare_stiffness(x);
  if (!system_.prepare(model, 1, h, h * h, free_, settings_.linear)) {
    report.finite = false;
    return report;
  }

  // rhs = h (f0 - h K v0)
  work_.setZero();
  model.add_stiffness_times(v, work_);
  rhs_ = h * (force_ - h * work_);

  // Known dv of the prescribed coordinates, moved to the right-hand side: rhs -= A dv_held.
  held_dv_.setZero();
  bool any_held_motion = false;
  if (prescribed.mask.rows() != 0) {
    for (Eigen::Index i = 0; i < n; ++i) {
      for (int a = 0; a < 3; ++a) {
        if (prescribed.mask(i, a) == 0) continue;
        held_dv_(i, a) = (prescribed.position(i, a) - x(i, a)) / h - v(i, a);
        any_held_motion = any_held_motion || held_dv_(i, a) != 0;
      }
    }
  }
  if (any_held_motion) {
    system_.apply_unconstrained(held_dv_, work_);
    rhs_ -= work_;
  }

  if (settings_.warm_start && has_last_dv_) {
    dv_ = last_dv_;
  } else {
    dv_.setZero();
  }
  CgReport cg = system_.solve(rhs_, dv_);
  const bool warm = settings_.warm_start && has_last_dv_;
  if (cg.breakdown && warm) {
    // Negative curvature (an indefinite K, e.g. Neo-Hookean with an inverted tet) can stop CG
    // before it improves the guess; kept, the last step's dv would be added again every step.
    // Start again from zero, where a breakdown leaves dv = 0 (no implicit correction this step).
    dv_.setZero();
    const int warm_iterations = cg.iterations;
    cg = system_.solve(rhs_, dv_);
    cg.iterations += warm_iterations;
  }
  report.iterations = cg.iterations;
  report.relative_residual = cg.relative_residual;
  report.converged = cg.converged;
  if (!all_finite(dv_)) {
    report.finite = false;
    report.converged = false;
    has_last_dv_ = false;
    return report;
  }
  // A broken-down solve is no guess for the next step.
  last_dv_ = dv_;
  has_last_dv_ = !cg.breakdown;

  dv_ += held_dv_;
  v += dv_;
  x += h * v;
  // Exactly on the prescribed values (x0 + h (target - x0) / h may differ in the last bit).
  if (prescribed.mask.rows() != 0) {
    for (Eigen::Index i = 0; i < n; ++i) {
      for (int a = 0; a < 3; ++a) {
        if (prescribed.mask(i, a) != 0) x(i, a) = prescribed.position(i, a);
      }
    }
  }
  return report;
}

}  // namespace incise::sim
