#include "sim/solve/adaptive_explicit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "sim/solve/free_coordinates.h"

namespace incise::sim {
namespace {

// Bogacki-Shampine 3(2): stages at 0, 1/2, 3/4, 1.
constexpr Real kB1 = Real(2) / 9, kB2 = Real(1) / 3, kB3 = Real(4) / 9;
// Third-order minus embedded second-order weights (7/24, 1/4, 1/3, 1/8).
constexpr Real kE1 = kB1 - Real(7) / 24, kE2 = kB2 - Real(1) / 4, kE3 = kB3 - Real(1) / 3,
               kE4 = -Real(1) / 8;

}  // namespace

AdaptiveExplicit::AdaptiveExplicit(AdaptiveExplicitSettings settings)
    : settings_(settings), dt_(settings.dt_initial) {
  const auto& s = settings_;
  if (!(s.position_tolerance > 0) || !(s.velocity_tolerance > 0) || !(s.dt_min > 0) ||
      !(s.dt_min <= s.dt_initial) || !(s.dt_initial <= s.dt_max) || s.max_steps < 1) {
    throw std::invalid_argument(
        "adaptive explicit needs tolerances > 0, 0 < dt_min <= dt_initial <= dt_max, "
        "max_steps >= 1");
  }
}

void AdaptiveExplicit::derivative(Model& model, const Points& x, const Points& v, Points& kx,
                                  Points& kv) {
  const VecX& m = model.masses();
  force_.setZero();
  model.add_forces(x, v, force_);
  if (external_->rows() != 0) force_ += *external_;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    for (int a = 0; a < 3; ++a) {
      if (free_(i, a) != 0) {
        kx(i, a) = v(i, a);
        kv(i, a) = force_(i, a) / m(i) + (*gravity_)(a);
      } else {
        kx(i, a) = held_velocity_(i, a);
        kv(i, a) = 0;
      }
    }
  }
}

ExplicitReport AdaptiveExplicit::advance(Real duration, const Vec3& gravity,
                                         const Points& external_forces,
                                         const Prescribed& prescribed, Model& model, Points& x,
                                         Points& v) {
  const VecX& m = model.masses();
  const Eigen::Index n = m.size();
  if (!(duration > 0)) throw std::invalid_argument("adaptive explicit: duration must be > 0");
  if (x.rows() != n || v.rows() != n ||
      (external_forces.rows() != 0 && external_forces.rows() != n)) {
    throw std::invalid_argument("adaptive explicit: x, v and external forces must be #nodes by 3");
  }
  check_prescribed(prescribed, static_cast<int>(n));
  if (force_.rows() != n) {
    for (Points* p : {&held_velocity_, &force_, &x_stage_, &v_stage_, &x_new_, &v_new_}) {
      p->resize(n, 3);
    }
    for (int k = 0; k < 4; ++k) {
      kx_[k].resize(n, 3);
      kv_[k].resize(n, 3);
    }
  }
  gravity_ = &gravity;
  external_ = &external_forces;
  free_coordinates(prescribed, m, free_);
  // Held coordinates: prescribed ones move at a constant velocity onto their position; massless
  // free nodes keep theirs.
  for (Eigen::Index i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      held_velocity_(i, a) = is_prescribed(prescribed, i, a)
                                 ? (prescribed.position(i, a) - x(i, a)) / duration
                                 : v(i, a);
      if (free_(i, a) == 0) v(i, a) = held_velocity_(i, a);
    }
  }

  ExplicitReport report;
  report.min_dt_used = std::numeric_limits<Real>::infinity();
  const Real inv_tol_x = 1 / settings_.position_tolerance;
  const Real inv_tol_v = 1 / settings_.velocity_tolerance;
  Real time = 0;
  derivative(model, x, v, kx_[0], kv_[0]);
  while (duration - time > 1e-12 * duration) {
    if (report.steps + report.rejected_steps >= settings_.max_steps) {
      report.completed = false;
      break;
    }
    const Real remaining = duration - time;
    const Real h = std::min(dt_, remaining);
    // Stages 2 and 3, then the third-order solution and its last stage.
    x_stage_ = x + (h / 2) * kx_[0];
    v_stage_ = v + (h / 2) * kv_[0];
    derivative(model, x_stage_, v_stage_, kx_[1], kv_[1]);
    x_stage_ = x + (3 * h / 4) * kx_[1];
    v_stage_ = v + (3 * h / 4) * kv_[1];
    derivative(model, x_stage_, v_stage_, kx_[2], kv_[2]);
    x_new_ = x + h * (kB1 * kx_[0] + kB2 * kx_[1] + kB3 * kx_[2]);
    v_new_ = v + h * (kB1 * kv_[0] + kB2 * kv_[1] + kB3 * kv_[2]);
    derivative(model, x_new_, v_new_, kx_[3], kv_[3]);
    const Real error_x =
        (h * (kE1 * kx_[0] + kE2 * kx_[1] + kE3 * kx_[2] + kE4 * kx_[3])).cwiseAbs().maxCoeff();
    const Real error_v =
        (h * (kE1 * kv_[0] + kE2 * kv_[1] + kE3 * kv_[2] + kE4 * kv_[3])).cwiseAbs().maxCoeff();
    Real error = std::max(error_x * inv_tol_x, error_v * inv_tol_v);
    const bool finite = std::isfinite(error) && all_finite(x_new_) && all_finite(v_new_);
    if (!finite) error = std::numeric_limits<Real>::infinity();
    // The floor: a step that cannot shrink any further (dt_min, or a last piece below it).
    const bool at_floor = h <= settings_.dt_min;
    const Real factor = std::clamp(Real(0.9) * std::pow(error, -Real(1) / 3), Real(0.2), Real(5));
    if (error > 1 && !at_floor) {
      ++report.rejected_steps;
      dt_ = std::max(settings_.dt_min, h * factor);
      continue;
    }
    if (!finite) {
      report.finite = false;
      report.completed = false;
      break;
    }
    if (error > 1) ++report.clamped_steps;
    x = x_new_;
    v = v_new_;
    std::swap(kx_[0], kx_[3]);
    std::swap(kv_[0], kv_[3]);
    time += h;
    ++report.steps;
    report.dt_used = h;
    report.min_dt_used = std::min(report.min_dt_used, h);
    report.error_estimate = std::max(report.error_estimate, error);
    // A last piece cut short says nothing about the step the error allows.
    if (h == dt_) dt_ = std::clamp(h * factor, settings_.dt_min, settings_.dt_max);
  }
  if (report.steps == 0) report.min_dt_used = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      if (is_prescribed(prescribed, i, a) && report.completed) x(i, a) = prescribed.position(i, a);
    }
  }
  return report;
}

}  // namespace incise::sim
