#pragma once

#include <string_view>

#include <nlohmann/json.hpp>

#include "curriculum/curriculum.h"
#include "curriculum/curriculum_error.h"

namespace incise::curriculum {

// Reads a curriculum from its JSON form (curriculum/demo/basic_skills.json is an example):
//   {"name", "description"?, "modules": [{"key", "name", "tasks": [{"key", "name", "scene",
//    "instructions"?, "tools"?: [string], "metrics": [{"key", "threshold": {"op": "<=" | ">=",
//    "value": number}, "unit"?}], "consecutive_passes_required": integer,
//    "prerequisites"?: [task key],
//    "protected_zones"?: [{"name", "center_m": [x, y, z], "radius_m", "never"?: bool}],
//    "targets"?: [{"name", "center_m": [x, y, z], "radius_m"}],
//    "safe_force_n"?: number, "never_force_n"?: number, "portal_m"?: [x, y, z]}]}]}
// Members marked ? may be left out (empty, false, or for the forces Task's defaults: 3 N, and 0
// for no never force). Lengths in metres, forces in newtons. Unknown members are rejected, so that
// a misspelt optional member is not silently ignored. After the shape, validate() runs. Throws
// CurriculumError naming the JSON path of the first problem, e.g.
//   modules[0].tasks[1].metrics[0].threshold.op: must be "<=" or ">="
Curriculum parse_curriculum(const nlohmann::json& json);

// The same from JSON text; a syntax error is a CurriculumError at the root.
Curriculum parse_curriculum_text(std::string_view text);

// The JSON form, every member written out; parse_curriculum(to_json(c)) == c for a valid c.
nlohmann::json to_json(const Curriculum& curriculum);

}  // namespace incise::curriculum
