#pragma once
// A deterministic device that plays a SimulatedScript: the tool tip moves piecewise-linearly
// between waypoints, the jaw likewise, the orientation stays constant. With jitter on, a smooth
// seeded tremor is added to the position.
//
// The state is a pure function of (script, t): two devices with the same script agree sample for
// sample at any polling rate, which is what tests and replays need.

#include <string>

#include "devices/device.h"
#include "devices/simulated_script.h"

namespace incise::devices {

class SimulatedDevice final : public Device {
 public:
  // Throws std::invalid_argument with check_simulated_script()'s text if the script is invalid.
  explicit SimulatedDevice(SimulatedScript script, std::string name = "simulated");

  std::string_view name() const override { return name_; }
  int degrees_of_freedom() const override { return 7; }  // pose + jaw
  DeviceCapabilities capabilities() const override;
  DeviceState poll(double t) override { return state_at(t); }

  // The state at t [s]; t < 0 reads as 0.
  DeviceState state_at(double t) const;

  const SimulatedScript& script() const { return script_; }

 private:
  SimulatedScript script_;
  std::string name_;
};

}  // namespace incise::devices
