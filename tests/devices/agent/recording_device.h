#pragma once
// A Device for agent tests: reports a tool tip the test sets and records every commanded force
// in a fixed buffer (no allocation, so the haptic loop's allocation check stays meaningful).

#include <array>
#include <atomic>
#include <cstddef>
#include <mutex>

#include "devices/device.h"

namespace incise::devices::agent::testing {

class RecordingDevice final : public Device {
 public:
  static constexpr std::size_t kCapacity = 1 << 14;  // forces kept; later ones overwrite the last

  std::string_view name() const override { return "recording"; }
  int degrees_of_freedom() const override { return 6; }
  DeviceCapabilities capabilities() const override { return {.has_force_output = true}; }

  DeviceState poll(double t) override {
    std::lock_guard lock(mutex_);
    last_poll_t_ = t;
    DeviceState s;
    s.position = position_;
    return s;
  }

  void set_force(const Vec3& force_n) override {
    std::lock_guard lock(mutex_);
    forces_[std::min(count_, kCapacity - 1)] = force_n;
    ++count_;
  }

  void set_position(const Vec3& p) {
    std::lock_guard lock(mutex_);
    position_ = p;
  }
  std::size_t force_count() const {
    std::lock_guard lock(mutex_);
    return count_;
  }
  // Precondition: force_count() > i, i < kCapacity.
  Vec3 force(std::size_t i) const {
    std::lock_guard lock(mutex_);
    return forces_[i];
  }
  Vec3 last_force() const {
    std::lock_guard lock(mutex_);
    return count_ == 0 ? Vec3{} : forces_[std::min(count_, kCapacity) - 1];
  }
  double last_poll_t() const {
    std::lock_guard lock(mutex_);
    return last_poll_t_;
  }

 private:
  mutable std::mutex mutex_;
  Vec3 position_;
  std::array<Vec3, kCapacity> forces_{};
  std::size_t count_ = 0;
  double last_poll_t_ = -1.0;
};

}  // namespace incise::devices::agent::testing
