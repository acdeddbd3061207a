#pragma once
// The interface every haptic device driver implements: simulated, replayed or a real SDK.
//
// poll() and set_force() are called from the haptic loop (1 kHz on the station), so
// implementations must not block, allocate or throw in them.

#include <string_view>

#include "devices/device_state.h"

namespace incise::devices {

struct DeviceCapabilities {
  bool has_force_output = false;  // set_force() renders a force on the user's hand
  bool has_jaw = false;           // DeviceState::jaw is measured, not constant
  int button_count = 0;           // DeviceState::buttons uses bits 0 .. button_count - 1
};

class Device {
 public:
  virtual ~Device() = default;

  // Human-readable, e.g. "simulated (built-in script)"; sent to the server in hello.
  virtual std::string_view name() const = 0;

  // Sensed degrees of freedom: 6 for a pose, plus 1 for a jaw.
  virtual int degrees_of_freedom() const = 0;

  virtual DeviceCapabilities capabilities() const = 0;

  // The device's state at time t [s] since the haptic loop started (t >= 0, non-decreasing).
  virtual DeviceState poll(double t) = 0;

  // Commands force_n [N] at the tool tip, station frame, until the next call. Devices without
  // force output ignore it, so the haptic loop need not ask.
  virtual void set_force(const Vec3& force_n) { (void)force_n; }
  // Empty while the device works; else what is wrong, e.g. "evdev: device unplugged". The haptic
  // loop's watchdog fades the force to zero while a fault is set. Called from the haptic loop
  // after poll(), so it must not block or allocate either.
  virtual std::string_view fault() const { return {}; }
};

}  // namespace incise::devices
