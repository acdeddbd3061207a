#pragma once
// What a haptic device reports in one sample. Shared by the drivers (which produce it) and the
// wire protocol (which carries it), so it depends on nothing.

#include <cstdint>

namespace incise::devices {

// A point or vector in the station frame [m] (forces in [N]).
struct Vec3 {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
  friend bool operator==(const Vec3&, const Vec3&) = default;
};

// A rotation as a unit quaternion, scalar first.
struct Quat {
  double w = 1.0;
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
  friend bool operator==(const Quat&, const Quat&) = default;
};

struct DeviceState {
  uint8_t device_index = 0;  // which device of the station (two-handed stations have 0 and 1)
  uint8_t buttons = 0;       // bit i set = button i pressed
  float jaw = 0.0f;          // jaw opening, 0 closed .. 1 fully open
  Vec3 position;             // tool tip [m], station frame
  Quat orientation;          // tool orientation, unit quaternion
  friend bool operator==(const DeviceState&, const DeviceState&) = default;
};

}  // namespace incise::devices
