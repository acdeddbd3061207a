#include "devices/simulated_hand.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace incise::devices {

SimulatedHand::SimulatedHand(SimulatedScript script, HandSettings settings, std::string name)
    : script_(std::move(script)), settings_(settings), name_(std::move(name)) {
  if (!(settings_.mass_kg > 0) || !(settings_.grip_stiffness_n_m > 0) ||
      !(settings_.grip_damping_ns_m >= 0)) {
    throw std::invalid_argument(
        "simulated hand: mass and grip stiffness must be > 0, damping >= 0");
  }
}

DeviceCapabilities SimulatedHand::capabilities() const {
  DeviceCapabilities caps = script_.capabilities();
  caps.has_force_output = true;
  return caps;
}

double SimulatedHand::kinetic_energy_j() const {
  const Vec3& v = velocity_;
  return 0.5 * settings_.mass_kg * (v.x * v.x + v.y * v.y + v.z * v.z);
}

DeviceState SimulatedHand::poll(double t) {
  DeviceState state = script_.state_at(t);
  if (!started_) {
    started_ = true;
    t_ = t;
    position_ = state.position;
  }
  const double span = t - t_;
  if (span > 0) {
    const int steps = std::max(1, static_cast<int>(std::ceil(span / 1e-4)));
    const double h = span / steps;
    const double m = settings_.mass_kg;
    const double k = settings_.grip_stiffness_n_m;
    const double b = settings_.grip_damping_ns_m;
    for (int i = 1; i <= steps; ++i) {
      const DeviceState target = script_.state_at(t_ + i * h);
      double* x[3] = {&position_.x, &position_.y, &position_.z};
      double* v[3] = {&velocity_.x, &velocity_.y, &velocity_.z};
      const double goal[3] = {target.position.x, target.position.y, target.position.z};
      const double f[3] = {force_.x, force_.y, force_.z};
      for (int axis = 0; axis < 3; ++axis) {
        // Semi-implicit: the grip's damping implicitly, so it is stable at any sub-step.
        const double accel_free = (k * (goal[axis] - *x[axis]) + f[axis]) / m;
        *v[axis] = (*v[axis] + h * accel_free) / (1.0 + h * b / m);
        *x[axis] += h * *v[axis];
        work_j_ += f[axis] * *v[axis] * h;
      }
    }
    t_ = t;
  }
  state.position = position_;
  return state;
}

}  // namespace incise::devices
