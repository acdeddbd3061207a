#pragma once
// What a task's scene id names, ready to simulate: a scene of the sim core (the palpation block:
// sim/scenes/*.json, a sim::Scene with sphere tools) or a surgical scene (sim/scenes/surgery/
// *.json: a liver or knee with probe, grasper, scalpel or scope bound to the station's devices,
// sim/surgery/). The id says which: surgical scenes live under "scenes/surgery/".
#include <memory>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "sim/render/camera.h"
#include "sim/scene/scene.h"
#include "sim/surgery/scene_presets.h"

namespace incise::server::live {

inline constexpr std::string_view kSurgicalScenePrefix = "scenes/surgery/";

class SessionScene {
 public:
  // Implicit: a sim::Scene is the common case (tests and the palpation tasks).
  SessionScene(sim::Scene block)
      : value_(std::move(block)) {}  // NOLINT(google-explicit-constructor)
  explicit SessionScene(std::shared_ptr<const sim::surgery::SurgicalSceneSetup> surgery)
      : value_(std::move(surgery)) {}

  // The sim core's scene, or nullptr for a surgical one.
  const sim::Scene* block() const { return std::get_if<sim::Scene>(&value_); }
  // The surgical scene (meshed, with its tools), or nullptr for a sim core scene.
  const std::shared_ptr<const sim::surgery::SurgicalSceneSetup>* surgery() const {
    return std::get_if<std::shared_ptr<const sim::surgery::SurgicalSceneSetup>>(&value_);
  }

 private:
  std::variant<sim::Scene, std::shared_ptr<const sim::surgery::SurgicalSceneSetup>> value_;
};

// Parses (and for a surgical scene meshes: about a second) the scene with this id and text.
// Throws sim::SceneError naming the JSON path of the first problem.
SessionScene load_session_scene(std::string_view id, std::string_view text);

// "" if a task's tools (tools[i] is held by device i) fit the scene, else why not: a surgical
// scene's tools are bound to devices, and the task must name each device's tool kind (e.g.
// "tools[0] is \"probe\" but the scene gives device 0 a scalpel"). A sim core scene's sphere
// tools stand for any tool.
std::string tools_mismatch(const SessionScene& scene, const std::vector<std::string>& tools);

// The camera the live view starts with: the scene's "view" if it has one; for a surgical scene a
// view of the whole tissue from above and in front, aimed halfway between the tissue's centre
// (of its bounding box) and the marked cut line's middle (the centre alone without a line).
render::Camera camera_for(const SessionScene& scene);

}  // namespace incise::server::live
