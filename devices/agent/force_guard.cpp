#include "devices/agent/force_guard.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Dense>

#include "devices/eigen_conversions.h"

namespace incise::devices::agent {
namespace {

double dot(const Vec3& a, const Vec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

// The slew limit lets a force component fall toward zero freely (the watchdog's fade must never
// be held back), and moves it otherwise by at most step. A force that changes sign drops to zero
// at once and rises from there: holding the old direction would push the hand the wrong way.
double slew(double previous, double desired, double step) {
  if (desired * previous < 0.0) previous = 0.0;
  const bool falling = std::abs(desired) <= std::abs(previous);
  if (falling) return desired;
  return std::clamp(desired, previous - step, previous + step);
}

}  // namespace

const char* to_string(GuardFault fault) {
  switch (fault) {
    case GuardFault::None:
      return "none";
    case GuardFault::LinkDown:
      return "link down";
    case GuardFault::NoModel:
      return "no model";
    case GuardFault::StaleModel:
      return "stale model";
    case GuardFault::DeviceFault:
      return "device fault";
    case GuardFault::BadState:
      return "bad device state";
    case GuardFault::LateTick:
      return "late tick";
    case GuardFault::Stopping:
      return "stopping";
  }
  return "?";
}

ForceGuardSettings ForceGuardSettings::transparent() {
  ForceGuardSettings settings;
  settings.coupling = false;
  settings.passivity = false;
  settings.max_force_n = {kMaxModelForce, kMaxModelForce, kMaxModelForce};
  settings.max_force_rate_n_s = 1e12;
  settings.max_speed_m_s = 1e12;
  return settings;
}

ForceGuard::ForceGuard(const ForceGuardSettings& settings) : settings_(settings) {}

void ForceGuard::reset() {
  tracking_ = false;
  velocity_ = {};
  displacement_ = {};
  energy_j_ = 0.0;
  previous_force_ = {};
  last_damping_ = 0.0;
}

Vec3 ForceGuard::track(const Vec3& position, double dt) {
  if (!tracking_ || !(dt > 0.0)) {
    tracking_ = true;
    position_ = position;
    displacement_ = {};
    return velocity_;
  }
  displacement_ = {position.x - position_.x, position.y - position_.y, position.z - position_.z};
  position_ = position;
  // First-order low pass: alpha = dt / (dt + 1 / (2 pi f_c)).
  const double tau = 1.0 / (2.0 * std::numbers::pi * settings_.velocity_cutoff_hz);
  const double alpha = dt / (dt + tau);
  velocity_.x += alpha * (displacement_.x / dt - velocity_.x);
  velocity_.y += alpha * (displacement_.y / dt - velocity_.y);
  velocity_.z += alpha * (displacement_.z / dt - velocity_.z);
  return velocity_;
}

Vec3 ForceGuard::couple(const Vec3& model_force, const std::array<double, 9>& stiffness,
                        double age_s) const {
  if (!settings_.coupling) return model_force;
  const double k =
      settings_.coupling_stiffness / (1.0 + std::max(age_s, 0.0) / settings_.softening_age_s);
  const Eigen::Matrix3d raw =
      Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(stiffness.data());
  // Only the stiffness that resists motion is coupled: the symmetric part with its negative
  // eigenvalues clamped to zero. A negative stiffness (the linearisation of a buckling contact,
  // or a bad model) would otherwise make K + kI near singular and amplify the force without
  // bound. So K + kI has eigenvalues >= k, and k (K + kI)^-1 never lengthens the model force.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(0.5 * (raw + raw.transpose()));
  if (eigen.info() != Eigen::Success) return {};
  const Eigen::Vector3d lambda = eigen.eigenvalues().cwiseMax(0.0);
  const Eigen::Matrix3d& V = eigen.eigenvectors();
  const Eigen::Matrix3d K = V * lambda.asDiagonal() * V.transpose();
  const Eigen::Vector3d inverse_diagonal = (lambda.array() + k).inverse();
  const Eigen::Matrix3d A_inv = V * inverse_diagonal.asDiagonal() * V.transpose();
  const Eigen::Vector3d coupled = k * (A_inv * to_eigen(model_force));
  const Eigen::Matrix3d share = K * A_inv;
  const Eigen::Vector3d damping = settings_.coupling_damping * (share * to_eigen(velocity_));
  return to_vec3(coupled - damping);
}

Vec3 ForceGuard::finish(const Vec3& desired, double dt, bool silent) {
  // The work the held force did on the hand over the interval that just ended: what the hand
  // received is taken from what the virtual side has absorbed.
  energy_j_ -= dot(previous_force_, displacement_);
  Vec3 force = desired;
  last_damping_ = 0.0;
  if (silent) {
    previous_force_ = {};
    return {};
  }
  if (settings_.passivity && dt > 0.0) {
    // Old credit leaks away, so energy absorbed long ago cannot pay for a burst now.
    if (energy_j_ > 0.0) {
      energy_j_ = std::min(energy_j_ * std::exp(-dt / settings_.reserve_leak_s),
                           settings_.energy_reserve_j);
    }
    // If the coming interval at the current velocity would leave the virtual side having
    // produced energy, damp by exactly the excess (capped).
    const double speed_squared = dot(velocity_, velocity_);
    const double predicted = energy_j_ - dot(force, velocity_) * dt;
    if (predicted < 0.0 && speed_squared > 1e-12) {
      const double alpha = std::min(-predicted / (speed_squared * dt), settings_.max_damping);
      force = {force.x - alpha * velocity_.x, force.y - alpha * velocity_.y,
               force.z - alpha * velocity_.z};
      last_damping_ = alpha;
      dissipated_j_ += alpha * speed_squared * dt;
    }
  }
  // The first tick has no interval yet: it may rise by one nominal tick's worth.
  const double step = settings_.max_force_rate_n_s * (dt > 0.0 ? dt : 1e-3);
  double* components[3] = {&force.x, &force.y, &force.z};
  const double previous[3] = {previous_force_.x, previous_force_.y, previous_force_.z};
  bool limited = false;
  for (int axis = 0; axis < 3; ++axis) {
    double& f = *components[axis];
    if (!std::isfinite(f)) f = 0.0;
    const double limit = settings_.max_force_n[axis];
    const double clamped = std::clamp(slew(previous[axis], f, step), -limit, limit);
    limited = limited || clamped != f;
    f = clamped;
  }
  if (limited) ++limited_ticks_;
  previous_force_ = force;
  return force;
}

}  // namespace incise::devices::agent
