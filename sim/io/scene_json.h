#pragma once

#include <filesystem>
#include <string_view>

#include <nlohmann/json.hpp>

#include "sim/scene/scene.h"
#include "sim/scene/scene_error.h"

namespace incise::sim {

// Reads a scene from its JSON form, the `incise solve` contract (sim/scenes/clamped_box.json is
// an example; units SI):
//   { "mesh": {"box": {"size": [Lx, Ly, Lz], "cells": [nx, ny, nz]}},
//     "material": {"model": "mss", "E": number, "nu": number, "density": number,
//                  "damping"?: number},
//     "constraints"?: [ {"where": {"box": [[x0, y0, z0], [x1, y1, z1]]}, "fix": "xyz"}
//                     | {"where": ..., "displace": [dx, dy, dz], "axes"?: "xyz"} ],
//     "loads"?: [ {"where": ..., "force": [fx, fy, fz]} ],
//     "gravity"?: [gx, gy, gz],
//     "solver": {"integrator": "symplectic_euler", "dt": number, "steps": integer},
//     "tool"?: {"radius"?: number, "stiffness"?: number, "damping"?: number},
//     "view"?: {"eye": [x, y, z], "target": [x, y, z], "up"?: [x, y, z], "fov_y_deg"?: number} }
// Members marked ? may be left out: damping 0.1, no constraints or loads, no gravity, a
// displace's axes "xyz", no tool (a tool's members default as in SphereTool), no view (its up
// +z, its fov_y_deg 45). "fix" and "axes" are non-empty subsets of "xyz" in any order. Unknown
// members are rejected, so that a misspelt optional member is not silently ignored. After the
// shape, validate_scene checks the value ranges.
// Throws SceneError naming the JSON path of the first problem, e.g.
//   material.E: must be positive (got -3)
Scene parse_scene(const nlohmann::json& json);

// The same from JSON text; a syntax error is a SceneError with an empty path whose reason says
// where ("malformed JSON: ...").
Scene parse_scene_text(std::string_view text);

// The same from a file; an unreadable file is a SceneError with an empty path.
Scene read_scene_file(const std::filesystem::path& file);

}  // namespace incise::sim
