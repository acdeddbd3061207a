#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace incise::sim {

// `incise surgery SCENE.json --script SCRIPT.json --out RESULT.json`: builds a surgical scene
// file (sim/surgery/scene_file.h), drives its tools by the script for the script's duration at
// the scene's dt, and writes RESULT.json (docs/surgical_scene_files.md):
//   {"scene", "scene_file", "script_file", "dt", "duration", "mass_scale", "steps", "nodes",
//    "tets", "setup_seconds", "wall_seconds", "real_time_ratio" (steps * dt / wall_seconds),
//    "steps_per_second", "finite", "status", "cuts_refused",
//    "mass_scaled_nodes", "max_mass_scale",
//    "events": [{"kind", "tool", "tool_kind", "time", "detail"}],
//    "damage": [{"name", "unit", "value"}]                  (tools::metric_rows, in their order)
//    "force_models": [{"device", "reference_position", "force", "stiffness"}]}
// and one summary line on out (steps, wall time, steps per second, events).
//   args  the arguments after "incise", starting with "surgery"
// Returns kExitOk; kExitUsage with one line on err naming the file and the JSON path for bad
// arguments or a bad scene or script, or an unwritable RESULT.json; kExitFailed if the state
// went non-finite (the run stops there; RESULT.json is written with "finite": false).
int run_surgery_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace incise::sim
