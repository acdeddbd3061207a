#pragma once

#include <nlohmann/json.hpp>

namespace incise::curriculum {

// A valid curriculum in JSON form with two modules, prerequisites across modules and both
// threshold ops; tests change one value of it at a time.
inline nlohmann::json sample_curriculum_json() {
  return nlohmann::json::parse(R"({
    "name": "Sample",
    "description": "Two modules for tests",
    "modules": [
      {"key": "basics", "name": "Basics", "tasks": [
        {"key": "palpation", "name": "Palpation", "scene": "scenes/palpation.json",
         "instructions": "Probe gently.", "tools": ["probe"],
         "metrics": [{"key": "peak_force_n", "threshold": {"op": "<=", "value": 4}, "unit": "N"}],
         "consecutive_passes_required": 3, "prerequisites": []},
        {"key": "grasping", "name": "Grasping", "scene": "scenes/grasping.json",
         "instructions": "Lift the flap.", "tools": ["grasper", "probe"],
         "metrics": [
           {"key": "targets_reached", "threshold": {"op": ">=", "value": 0.9}, "unit": ""},
           {"key": "completion_time_s", "threshold": {"op": "<=", "value": 95.5}, "unit": "s"}],
         "consecutive_passes_required": 2, "prerequisites": ["palpation"]}]},
      {"key": "cutting", "name": "Cutting", "tasks": [
        {"key": "incision", "name": "Straight incision", "scene": "scenes/incision.json",
         "instructions": "Cut along the line.", "tools": ["scalpel", "grasper"],
         "metrics": [{"key": "damage_mm3", "threshold": {"op": "<=", "value": 20}, "unit": "mm^3"}],
         "consecutive_passes_required": 1, "prerequisites": ["grasping", "palpation"]}]}
    ]
  })");
}

}  // namespace incise::curriculum
