#pragma once
// The script a SimulatedDevice plays: tool-tip waypoints in time, as JSON
//
//   {"seed": 7, "loop": true, "jitter": 0.0002,
//    "orientation": [1, 0, 0, 0],
//    "waypoints": [{"t": 0.0, "position": [0.0, 0.0, 0.1], "jaw": 0.0}, ...]}
//
// required: waypoints   at least one; t [s] >= 0 and strictly increasing; position [m]; jaw in
//                       [0, 1], default 0
// optional: seed        non-negative integer for the jitter, default 0
//           loop        after the last waypoint restart from t = 0 (period = last t), default false
//           jitter      amplitude [m] of a seeded, smooth tremor added to each axis, default 0
//           orientation constant unit quaternion w, x, y, z, default identity
// Unknown keys are errors, so that a misspelt key does not silently fall back to a default.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "devices/device_state.h"
#include "devices/parse_result.h"

namespace incise::devices {

struct Waypoint {
  double t = 0.0;  // [s]
  Vec3 position;   // tool tip [m]
  double jaw = 0.0;
};

struct SimulatedScript {
  uint64_t seed = 0;
  bool loop = false;
  double jitter = 0.0;  // [m]
  Quat orientation;
  std::vector<Waypoint> waypoints;
};

// Errors read `<key path>: <problem>`, e.g. `waypoints[2].position[1]: must be a number, got
// string`, or `not valid JSON: ...` with the line and column.
ParseResult<SimulatedScript> parse_simulated_script(std::string_view json_text);

// The first rule of the format above that script breaks, as `<key path>: <problem>`, or "".
std::string check_simulated_script(const SimulatedScript& script);

// 20 s of pressing, sliding and grasping on the demo scene's tissue block (x, y in [0, 0.08] m,
// top surface z = 0.03 m), looping, with a little tremor: the agent plays it when no script file
// is given.
std::string_view default_simulated_script();

}  // namespace incise::devices
