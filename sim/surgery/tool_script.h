#pragma once

// Scripted tool sequences for a surgical scene (docs/surgical_scene_files.md), as the incise CLI
// runs them; track_sampling.h samples them in time. Units SI; members marked ? may be left out.
//
// Script file: one keyframed track per device.
//   { "description"?: "free text",
//     "duration": seconds > 0,
//     "devices": [ {"keyframes": [ keyframe, ... ]}, ... ] }     (devices[d] drives device d)
//   keyframe: { "t": seconds in [0, duration], strictly increasing along a track,
//               "tip": [x, y, z] | "at": "<place>" with "offset"?: [dx, dy, dz],
//               "direction"?: [dx, dy, dz] | "towards": "<place>" | "from": "<place>" |
//                             "along": "<portal>",
//               "advance"?: metres along the direction,
//               "jaw"?: opening in [0, 1] }
//   A place is a landmark or a portal of the scene, or "cut_start" / "cut_end" (the ends of the
//   marked cut line). The tip is (tip, or the place + offset) + advance * direction. "towards"
//   points from (tip, or place + offset) to the named place, "from" from the named place to it
//   (a tool that entered through that portal); "along" takes the portal's
//   direction. direction and jaw carry over from the previous keyframe (the first's: straight
//   down [0, 0, -1], and 1, open).
// Between keyframes the tip and the jaw are interpolated linearly and the direction normalised-
// lerped (n((1 - s) d0 + s d1)); before the first keyframe and after the last a track holds.
// The tool's orientation is the shortest rotation taking e_z onto the direction (its roll about
// the direction is not scripted). A tool on a device the script has no track for gets no input
// (it is never placed); a track for a device no tool uses is refused.
//
//
// Errors: SceneError naming the JSON path, e.g.
//   devices[0].keyframes[2].t: must be after the previous keyframe's (0.5) (got 0.5)

#include <filesystem>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/core/types.h"
#include "sim/scene/scene_error.h"
#include "sim/surgery/scene_presets.h"

namespace incise::sim::surgery {

// One resolved keyframe of a device's track.
struct Keyframe {
  Real t = 0;                       // [s]
  Vec3 tip = Vec3::Zero();          // [m], scene frame
  Vec3 direction = -Vec3::UnitZ();  // unit
  Real jaw = 1;                     // [0, 1]
};

struct DeviceTrack {
  std::vector<Keyframe> keyframes;  // at least one, t strictly increasing
};

struct ToolScript {
  Real duration = 0;                 // [s], > 0
  std::vector<DeviceTrack> devices;  // devices[d] drives device d
};

// Reads a script for the given scene (its places resolve "at", "towards" and "along"; its tools
// say which devices exist). Throws SceneError at the first problem's JSON path.
ToolScript parse_tool_script(const nlohmann::json& value, const SurgicalSceneSetup& scene);
ToolScript parse_tool_script_text(std::string_view text, const SurgicalSceneSetup& scene);
ToolScript read_tool_script(const std::filesystem::path& file, const SurgicalSceneSetup& scene);

}  // namespace incise::sim::surgery
