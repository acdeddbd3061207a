#pragma once
// A task's named material (docs/calibration.md) applied to its scene: the scene text with the
// material's constants in place of its own, so that a live session and its replay build the same
// body from one text, and the recording's scene version (its hash) covers the material too.
#include <string>
#include <string_view>

namespace incise::server::live {

// The sim core scene text with the material's constants:
//   constants  {"material": {"E", "nu", "density", "damping"}, "materials"?: {"<label>": {...}}}
//              (a materials row, db/calibration_repo.h), calibrated for the model `model`
// The scene's "material" takes E, nu, density and damping (and for the mass-spring model the
// volume term the fit had, none if it had none); its "materials" is replaced by the material's
// (or dropped when the material has none: its constants stand for the whole tissue). Throws
// std::invalid_argument, in a sentence, for a surgical scene, a scene whose model is not `model`,
// or malformed constants.
std::string scene_with_material(std::string_view scene_id, std::string_view scene_text,
                                std::string_view constants, std::string_view model);

}  // namespace incise::server::live
