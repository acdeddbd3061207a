#pragma once
// The driver seam (docs/device_drivers.md): device drivers register by name, and the agent opens
// each hand's device from a spec "NAME[:ARGUMENT]" (--device). The simulated, simulated-hand and
// replay drivers always exist; evdev (3D mice) on Linux; a vendor SDK driver only in builds that
// found its SDK (INCISE_WITH_OPENHAPTICS).
//
// Opening may allocate, read files and talk to hardware; only the opened Device's poll() and
// set_force() are held to the haptic loop's rules.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "devices/device.h"
#include "devices/parse_result.h"

namespace incise::devices {

using DeviceResult = ParseResult<std::unique_ptr<Device>>;
// Opens a device from the spec's argument (empty if the spec has none). Errors name the driver
// and what is wrong, e.g. `evdev /dev/input/event5: Permission denied`.
using DriverFactory = std::function<DeviceResult(const std::string& argument)>;

struct DriverInfo {
  std::string name;
  std::string usage;  // e.g. "simulated[:SCRIPT.json]  scripted tool motion, no force output"
};

class DriverRegistry {
 public:
  // Replaces a driver of the same name.
  void add(const std::string& name, const std::string& usage, DriverFactory factory);
  // Errors: `--device NAME: unknown driver (have simulated, hand, replay, evdev)` or the
  // driver's own.
  DeviceResult open(const std::string& spec) const;
  std::vector<DriverInfo> list() const;

 private:
  struct Entry {
    DriverInfo info;
    DriverFactory factory;
  };
  std::vector<Entry> entries_;
};

// The drivers of this build.
const DriverRegistry& builtin_drivers();

}  // namespace incise::devices
