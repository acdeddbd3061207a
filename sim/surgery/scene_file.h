#pragma once

// Surgical scenes as files, and scripted tool sequences to run them with
// (docs/surgical_scene_files.md). Units SI; members marked ? may be left out.
//
// Scene file: the preset of scene_presets.h and its options. Every member but "anatomy" is
// optional and defaults to the preset's value.
//   { "description"?: "free text",
//     "anatomy": "liver" | "knee",
//     "anatomy_options"?: liver: {"centre", "length", "cell_size", "cut_length", "cut_points"}
//                         knee:  {"voxel_size", "tissue_cell_size", "bone_facet_size",
//                                 "flexion_deg"}                      (LiverOptions, KneeOptions)
//     "materials"?: {"<tissue>": {"model"?, "E"?, "nu"?, "density"?, "damping"?}}
//                   tissues: liver: "liver"; knee: "meniscus", "ligament"; model one of mss,
//                   linear, corotational, corotational_polar, stvk, neohookean
//     "tools"?: [ {"kind": "probe" | "grasper" | "scalpel" | "scope", "device": integer >= 0,
//                  per-kind settings, each optional} ]     (absent: the preset's default tools)
//     "damage"?: {"strain_threshold"?, "target_half_width"?},
//     "solver"?: {"cut_every"?, "damage_every"?} }
// A tool starts from the preset's default tool of its kind (the knee's probe has a 1.5 mm hook
// tip, its scope a 4 mm shaft), else from ToolSpec's defaults. Its settings and the kinds they
// belong to: shaft_length, shaft_radius (all); radius (probe); coupling_stiffness, max_force
// (probe, scope); tear_force, jaw_length, reach, max_jaw_angle [rad] (grasper); blade_length
// (scalpel);
// view_angle_degrees, field_of_view_degrees (scope). A setting on a kind it does not belong to is
// refused, as is any unknown member. The time step is the preset's (the tissue's stable step).
//
// Script file: one keyframed track per device.
//   { "description"?: "free text",
//     "duration": seconds > 0,
//     "devices": [ {"keyframes": [ keyframe, ... ]}, ... ] }     (devices[d] drives device d)
//   keyframe: { "t": seconds in [0, duration], strictly increasing along a track,
//               "tip": [x, y, z] | "at": "<place>" with "offset"?: [dx, dy, dz],
//               "direction"?: [dx, dy, dz] | "towards": "<place>" | "along": "<portal>",
//               "advance"?: metres along the direction,
//               "jaw"?: opening in [0, 1] }
//   A place is a landmark or a portal of the scene, or "cut_start" / "cut_end" (the ends of the
//   marked cut line). The tip is (tip, or the place + offset) + advance * direction. "towards"
//   points from (tip, or place + offset) to the named place; "along" takes the portal's
//   direction. direction and jaw carry over from the previous keyframe (the first's: straight
//   down [0, 0, -1], and 1, open).
// Between keyframes the tip and the jaw are interpolated linearly and the direction normalised-
// lerped (n((1 - s) d0 + s d1)); before the first keyframe and after the last a track holds.
// The tool's orientation is the shortest rotation taking e_z onto the direction (its roll about
// the direction is not scripted). A tool on a device the script has no track for gets no input
// (it is never placed); a track for a device no tool uses is refused.
//
// Errors: SceneError naming the JSON path, e.g.
//   tools[1].kind: "saw" is not one of probe, grasper, scalpel, scope
//   devices[0].keyframes[2].t: must be after the previous keyframe's (0.5) (got 0.5)

#include <filesystem>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/core/types.h"
#include "sim/scene/scene_error.h"
#include "sim/surgery/scene_presets.h"
#include "sim/surgery/surgical_scene.h"

namespace incise::sim::surgery {

enum class Anatomy { liver, knee };

// A scene file's content, before any meshing: the preset to build and its options.
struct SurgicalSceneFile {
  Anatomy anatomy = Anatomy::liver;
  LiverSceneOptions liver;  // when anatomy is liver
  KneeSceneOptions knee;    // when anatomy is knee
  int cut_every = SurgicalSceneSpec{}.cut_every;
  int damage_every = SurgicalSceneSpec{}.damage_every;
};

// Reads and validates a scene file's JSON (shapes, value ranges, the anatomy's option ranges).
// Throws SceneError at the first problem's JSON path.
SurgicalSceneFile parse_surgical_scene_file(const nlohmann::json& value);

// The scene of a parsed file, through make_liver_surgery / make_knee_surgery (meshes the
// anatomy: about a second at the default options). Throws as they do.
SurgicalSceneSetup build_surgical_scene(const SurgicalSceneFile& file);

// Both steps from JSON text (a syntax error is a SceneError with an empty path, "malformed
// JSON: ...") or from a file (an unreadable file likewise).
SurgicalSceneSetup parse_surgical_scene(std::string_view text);
SurgicalSceneSetup read_surgical_scene(const std::filesystem::path& file);

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

// The track's input at time t [s] (held before the first and after the last keyframe).
// Allocates nothing. Precondition: track has a keyframe.
ToolInput sample_track(const DeviceTrack& track, Real t);

// Every device's input at time t into inputs (resized to the script's device count; no
// allocation once it has that size).
void sample_script(const ToolScript& script, Real t, std::vector<ToolInput>& inputs);

}  // namespace incise::sim::surgery
