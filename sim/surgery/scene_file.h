#pragma once

// Surgical scenes as files (docs/surgical_scene_files.md); the scripts that drive their tools are
// in tool_script.h. Units SI; members marked ? may be left out.
//
// Scene file: the preset of scene_presets.h and its options. Every member but "anatomy" is
// optional and defaults to the preset's value.
//   { "description"?: "free text",
//     "anatomy": "liver" | "knee",
//     "anatomy_options"?: liver: {"centre", "length", "cell_size", "cut_length", "cut_points"}
//                         knee:  {"voxel_size", "tissue_cell_size", "bone_facet_size",
//                                 "flexion_deg"}                      (LiverOptions, KneeOptions)
//     "materials"?: {"<tissue>": {"model"?, "E"?, "nu"?, "density"?, "damping"?, "toughness"?}}
//                   tissues: liver: "liver"; knee: "meniscus", "ligament"; model one of mss,
//                   linear, corotational, corotational_polar, corotational_nodal_pressure,
//                   stvk, neohookean; toughness [J/m^2]
//                   >= 0, the work to cut a unit area (the scalpel's resistance; the preset's:
//                   liver 200, meniscus 500, ligament 1000)
//     "tools"?: [ {"kind": "probe" | "grasper" | "scalpel" | "scope", "device": integer >= 0,
//                  per-kind settings, each optional} ]     (absent: the preset's default tools)
//     "damage"?: {"strain_threshold"?, "target_half_width"?},
//     "solver"?: {"cut_every"?, "damage_every"?, "time_step"?} }
// time_step [s] in [0, 0.01]: longer than the tissue's stable step, the tissue is mass-scaled
// to make it stable (SurgicalSceneSetup::mass_scale); otherwise, and by default, the step is the
// stable step.
// A tool starts from the preset's default tool of its kind (the knee's probe has a 1.5 mm hook
// tip, its scope a 4 mm shaft), else from ToolSpec's defaults. Its settings and the kinds they
// belong to: shaft_length, shaft_radius (all); radius (probe); coupling_stiffness, max_force
// (probe, scope); tear_force, jaw_length, reach, max_jaw_angle [rad] (grasper); blade_length
// (scalpel);
// view_angle_degrees, field_of_view_degrees (scope). A setting on a kind it does not belong to is
// refused, as is any unknown member. The time step is the tissue's stable step unless
// solver.time_step asks for more.
//
// Errors: SceneError naming the JSON path, e.g.
//   tools[1].kind: "saw" is not one of probe, grasper, scalpel, scope

#include <filesystem>
#include <string_view>

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

}  // namespace incise::sim::surgery
