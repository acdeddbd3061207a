#include "devices/driver_registry.h"

#include <fstream>
#include <sstream>

#include "devices/simulated_device.h"
#include "devices/simulated_hand.h"
#include "devices/simulated_scope.h"
#include "devices/simulated_script.h"
#include "devices/state_log.h"

#if defined(__linux__)
#include "devices/drivers/evdev_device.h"
#endif
#if defined(INCISE_WITH_OPENHAPTICS)
#include "devices/drivers/openhaptics_device.h"
#endif

namespace incise::devices {
namespace {

// The script at path, or the built-in one for an empty path.
ParseResult<SimulatedScript> load_script(const std::string& driver, const std::string& path) {
  using Result = ParseResult<SimulatedScript>;
  std::string text(default_simulated_script());
  if (!path.empty()) {
    std::ifstream file(path, std::ios::binary);
    if (!file) return Result::failure(driver + " " + path + ": cannot open");
    std::ostringstream buffer;
    buffer << file.rdbuf();
    text = buffer.str();
  }
  auto script = parse_simulated_script(text);
  if (!script) {
    return Result::failure(driver + " " + (path.empty() ? std::string("(built-in script)") : path) +
                           ": " + script.error);
  }
  return script;
}

std::string script_name(const std::string& path) {
  if (path.empty()) return "built-in script";
  const auto slash = path.rfind('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

DriverRegistry make_builtin() {
  DriverRegistry registry;
  registry.add("simulated",
               "simulated[:SCRIPT.json]  scripted tool motion (built-in script by default)",
               [](const std::string& path) -> DeviceResult {
                 auto script = load_script("simulated", path);
                 if (!script) return DeviceResult::failure(script.error);
                 return DeviceResult::success(std::make_unique<SimulatedDevice>(
                     std::move(*script.value), "simulated (" + script_name(path) + ")"));
               });
  registry.add("hand",
               "hand[:SCRIPT.json]  a simulated hand on a force-feedback device: follows the "
               "script through a grip spring and feels the force",
               [](const std::string& path) -> DeviceResult {
                 auto script = load_script("hand", path);
                 if (!script) return DeviceResult::failure(script.error);
                 return DeviceResult::success(
                     std::make_unique<SimulatedHand>(std::move(*script.value), HandSettings{},
                                                     "simulated hand (" + script_name(path) + ")"));
               });
  registry.add("scope",
               "scope[:SCRIPT.json]  a simulated 4-DOF scope at a portal above the demo block: "
               "the script's tip targets through the fulcrum kinematics, forces on pitch, yaw and "
               "insertion",
               [](const std::string& path) -> DeviceResult {
                 auto script = load_script("scope", path);
                 if (!script) return DeviceResult::failure(script.error);
                 return DeviceResult::success(std::make_unique<SimulatedScope>(
                     std::move(*script.value), demo_scope_geometry(),
                     "simulated scope (" + script_name(path) + ")"));
               });
  for (const bool lateral : {true, false}) {
    const std::string name = lateral ? "knee-scope" : "knee-instrument";
    registry.add(
        name,
        name + ":SCRIPT.json  a simulated " +
            (lateral ? "arthroscope at the knee's anterolateral portal"
                     : "instrument at the knee's anteromedial portal") +
            ": the script's tip targets (knee scene frame) through the portal's fulcrum",
        [name, lateral](const std::string& path) -> DeviceResult {
          if (path.empty())
            return DeviceResult::failure(name + ": needs a script (" + name + ":SCRIPT.json)");
          auto script = load_script(name, path);
          if (!script) return DeviceResult::failure(script.error);
          return DeviceResult::success(std::make_unique<SimulatedScope>(
              std::move(*script.value), knee_portal_geometry(lateral),
              "simulated " + name + " (" + script_name(path) + ")"));
        });
  }
  registry.add("replay", "replay:FILE[,device=N][,once]  plays a --record-states log",
               [](const std::string& argument) { return ReplayDevice::open(argument); });
#if defined(__linux__)
  registry.add("evdev",
               "evdev[:/dev/input/eventN]  a 6-DOF 3D mouse through Linux evdev, no force output "
               "(the first one found by default)",
               [](const std::string& path) -> DeviceResult {
                 auto device = EvdevDevice::open(path, EvdevSettings{});
                 if (!device) return DeviceResult::failure(device.error);
                 return DeviceResult::success(std::move(*device.value));
               });
#endif
#if defined(INCISE_WITH_OPENHAPTICS)
  registry.add("openhaptics",
               "openhaptics[:DEVICE_NAME]  a 3D Systems Touch/Phantom via OpenHaptics",
               [](const std::string& name) -> DeviceResult {
                 auto device = OpenHapticsDevice::open(name);
                 if (!device) return DeviceResult::failure(device.error);
                 return DeviceResult::success(std::move(*device.value));
               });
#endif
  return registry;
}

}  // namespace

void DriverRegistry::add(const std::string& name, const std::string& usage, DriverFactory factory) {
  for (Entry& entry : entries_) {
    if (entry.info.name == name) {
      entry = {{name, usage}, std::move(factory)};
      return;
    }
  }
  entries_.push_back({{name, usage}, std::move(factory)});
}

DeviceResult DriverRegistry::open(const std::string& spec) const {
  const auto colon = spec.find(':');
  const std::string name = spec.substr(0, colon);
  const std::string argument = colon == std::string::npos ? "" : spec.substr(colon + 1);
  for (const Entry& entry : entries_) {
    if (entry.info.name == name) return entry.factory(argument);
  }
  std::string known;
  for (const Entry& entry : entries_)
    known += (known.empty() ? "" : ", ") + entry.info.name;
  return DeviceResult::failure("--device " + spec + ": unknown driver (have " + known + ")");
}

std::vector<DriverInfo> DriverRegistry::list() const {
  std::vector<DriverInfo> out;
  for (const Entry& entry : entries_)
    out.push_back(entry.info);
  return out;
}

const DriverRegistry& builtin_drivers() {
  static const DriverRegistry registry = make_builtin();
  return registry;
}

}  // namespace incise::devices
