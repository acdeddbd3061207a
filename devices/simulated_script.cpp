#include "devices/simulated_script.h"

#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "devices/json_read.h"

#include "devices/protocol.h"

namespace incise::devices {
namespace {

using nlohmann::json;
using namespace json_read;

// The tremor of a resting hand is a fraction of a millimetre; more than a centimetre is a typo.
constexpr double kMaxJitter = 0.01;

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

std::string read_waypoint(const json& value, const std::string& path, Waypoint& waypoint) {
  if (!value.is_object()) return wrong_type(path, "an object", value);
  for (const char* key : {"t", "position"}) {
    if (!value.contains(key)) return path + "." + key + ": missing";
  }
  for (const auto& [key, field] : value.items()) {
    const std::string field_path = path + "." + key;
    std::string error;
    if (key == "t") {
      error = read_number(field, field_path, waypoint.t);
    } else if (key == "position") {
      double p[3];
      error = read_numbers(field, field_path, 3, p);
      waypoint.position = {p[0], p[1], p[2]};
    } else if (key == "jaw") {
      error = read_number(field, field_path, waypoint.jaw);
    } else {
      error = field_path + ": unknown key (a waypoint has t, position and jaw)";
    }
    if (!error.empty()) return error;
  }
  return {};
}

std::string read_script(const json& root, SimulatedScript& script) {
  if (!root.is_object()) return wrong_type("(script)", "an object", root);
  if (!root.contains("waypoints")) return "waypoints: missing";
  for (const auto& [key, value] : root.items()) {
    std::string error;
    if (key == "seed") {
      if (!value.is_number_unsigned()) {
        error = value.is_number_integer()
                    ? "seed: must be a non-negative integer, got " + value.dump()
                    : wrong_type(key, "a non-negative integer", value);
      } else {
        script.seed = value.get<uint64_t>();
      }
    } else if (key == "loop") {
      if (!value.is_boolean()) {
        error = wrong_type(key, "true or false", value);
      } else {
        script.loop = value.get<bool>();
      }
    } else if (key == "jitter") {
      error = read_number(value, key, script.jitter);
    } else if (key == "orientation") {
      double q[4];
      error = read_numbers(value, key, 4, q);
      script.orientation = {q[0], q[1], q[2], q[3]};
    } else if (key == "waypoints") {
      if (!value.is_array()) {
        error = wrong_type(key, "an array", value);
      } else {
        script.waypoints.resize(value.size());
        for (std::size_t i = 0; i < value.size() && error.empty(); ++i) {
          error = read_waypoint(value[i], index_path(key, i), script.waypoints[i]);
        }
      }
    } else {
      error = key + ": unknown key (expected seed, loop, jitter, orientation or waypoints)";
    }
    if (!error.empty()) return error;
  }
  return {};
}

}  // namespace

ParseResult<SimulatedScript> parse_simulated_script(std::string_view json_text) {
  json root;
  try {
    root = json::parse(json_text);
  } catch (const json::exception& e) {
    // A syntax error, or a number beyond a double's range (out_of_range 406). Drop nlohmann's
    // "[json.exception.parse_error.101] " prefix; keep line, column and cause.
    const std::string what = e.what();
    const auto cut = what.find("] ");
    return ParseResult<SimulatedScript>::failure(
        "not valid JSON: " + (cut == std::string::npos ? what : what.substr(cut + 2)));
  }
  SimulatedScript script;
  std::string error = read_script(root, script);
  if (error.empty()) error = check_simulated_script(script);
  if (!error.empty()) return ParseResult<SimulatedScript>::failure(std::move(error));
  return ParseResult<SimulatedScript>::success(std::move(script));
}

std::string check_simulated_script(const SimulatedScript& script) {
  if (!(script.jitter >= 0.0 && script.jitter <= kMaxJitter)) {
    return "jitter: must be in [0, " + number(kMaxJitter) + "] m, got " + number(script.jitter);
  }
  const Quat& q = script.orientation;
  const double norm = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  if (!(std::abs(norm - 1.0) <= kUnitQuaternionTolerance)) {
    return "orientation: must be a unit quaternion, got |q| = " + number(norm);
  }
  const auto& waypoints = script.waypoints;
  if (waypoints.empty()) return "waypoints: must have at least one waypoint";
  for (std::size_t i = 0; i < waypoints.size(); ++i) {
    const Waypoint& w = waypoints[i];
    const std::string path = index_path("waypoints", i);
    if (!std::isfinite(w.t) || w.t < 0.0) return path + ".t: must be >= 0, got " + number(w.t);
    if (i > 0 && !(w.t > waypoints[i - 1].t)) {
      return path + ".t: must be greater than the previous waypoint's t (" +
             number(waypoints[i - 1].t) + "), got " + number(w.t);
    }
    if (!std::isfinite(w.position.x) || !std::isfinite(w.position.y) ||
        !std::isfinite(w.position.z)) {
      return path + ".position: must be finite";
    }
    if (!(w.jaw >= 0.0 && w.jaw <= 1.0)) {
      return path + ".jaw: must be in [0, 1], got " + number(w.jaw);
    }
  }
  if (script.loop && !(waypoints.back().t > 0.0)) {
    return "loop: needs the last waypoint at t > 0 (its t is the loop period)";
  }
  return {};
}

std::string_view default_simulated_script() {
  // Palpates the demo scene's tissue block (x, y in [0, 0.08] m, top surface at z = 0.03 m) with
  // a 5 mm tip: from rest above the block centre, press until the tip centre is at z = 0.029
  // (6 mm into the surface), slide 2.2 cm, lift, grasp and slide at a second site, return.
  // Station frame = scene frame. The last waypoint equals the first so the 20 s loop is seamless.
  return R"({
  "seed": 1,
  "loop": true,
  "jitter": 0.0002,
  "orientation": [1, 0, 0, 0],
  "waypoints": [
    {"t": 0.0, "position": [0.040, 0.040, 0.060], "jaw": 0.0},
    {"t": 2.0, "position": [0.040, 0.040, 0.036], "jaw": 0.0},
    {"t": 3.0, "position": [0.040, 0.040, 0.029], "jaw": 0.0},
    {"t": 4.0, "position": [0.040, 0.040, 0.029], "jaw": 0.0},
    {"t": 7.0, "position": [0.060, 0.050, 0.029], "jaw": 0.0},
    {"t": 8.0, "position": [0.060, 0.050, 0.045], "jaw": 0.0},
    {"t": 9.5, "position": [0.020, 0.025, 0.045], "jaw": 0.0},
    {"t": 10.5, "position": [0.020, 0.025, 0.040], "jaw": 0.8},
    {"t": 11.5, "position": [0.020, 0.025, 0.029], "jaw": 0.8},
    {"t": 12.0, "position": [0.020, 0.025, 0.029], "jaw": 0.1},
    {"t": 14.5, "position": [0.030, 0.055, 0.029], "jaw": 0.1},
    {"t": 15.5, "position": [0.030, 0.055, 0.050], "jaw": 0.6},
    {"t": 17.5, "position": [0.040, 0.040, 0.060], "jaw": 0.0},
    {"t": 20.0, "position": [0.040, 0.040, 0.060], "jaw": 0.0}
  ]
})";
}

}  // namespace incise::devices
