#include "sim/solve/central_difference.h"

#include <stdexcept>

#include "sim/solve/free_coordinates.h"

namespace incise::sim {

void CentralDifference::half_kick(Real h, const Vec3& gravity, const Points& external_forces,
                                  const VecX& m, Points& v) const {
  const bool has_external = external_forces.rows() != 0;
  for (Eigen::Index i = 0; i < v.rows(); ++i) {
    if (!(m(i) > 0)) continue;
    Eigen::Matrix<Real, 1, 3> f = force_.row(i);
    if (has_external) f += external_forces.row(i);
    v.row(i) += (Real(0.5) * h) * (f / m(i) + gravity.transpose());
  }
}

ExplicitReport CentralDifference::step(Real h, const Vec3& gravity, const Points& external_forces,
                                       const Prescribed& prescribed, Model& model, Points& x,
                                       Points& v) {
  const VecX& m = model.masses();
  const Eigen::Index n = m.size();
  if (!(h > 0)) throw std::invalid_argument("central difference step needs h > 0");
  if (x.rows() != n || v.rows() != n ||
      (external_forces.rows() != 0 && external_forces.rows() != n)) {
    throw std::invalid_argument("central difference: x, v and external forces must be #nodes by 3");
  }
  check_prescribed(prescribed, static_cast<int>(n));
  if (force_.rows() != n) {
    force_.resize(n, 3);
    x_end_.resize(n, 3);
    v_end_.resize(n, 3);
    has_force_ = false;
  }
  // The kept forces hold only if nobody moved the state since the last step.
  if (!has_force_ || x != x_end_ || v != v_end_) {
    force_.setZero();
    model.add_forces(x, v, force_);
    x_end_ = x;
    v_end_ = v;
  }
  ExplicitReport report;
  report.dt_used = h;
  report.min_dt_used = h;

  half_kick(h, gravity, external_forces, m, v);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      if (is_prescribed(prescribed, i, a)) {
        v(i, a) = (prescribed.position(i, a) - x(i, a)) / h;
        x(i, a) = prescribed.position(i, a);
      } else {
        x(i, a) += h * v(i, a);
      }
    }
  }
  force_.setZero();
  model.add_forces(x, v, force_);
  half_kick(h, gravity, external_forces, m, v);
  // The second kick must not move prescribed velocities off (position - x_n) / h.
  for (Eigen::Index i = 0; i < n && prescribed.mask.rows() != 0; ++i) {
    for (int a = 0; a < 3; ++a) {
      if (prescribed.mask(i, a) != 0) {
        v(i, a) = (prescribed.position(i, a) - x_end_(i, a)) / h;
      }
    }
  }

  if (!all_finite(x) || !all_finite(v) || !all_finite(force_)) {
    x = x_end_;
    v = v_end_;
    has_force_ = false;
    report.finite = false;
    report.completed = false;
    return report;
  }
  x_end_ = x;
  v_end_ = v;
  has_force_ = true;
  report.steps = 1;
  return report;
}

}  // namespace incise::sim
