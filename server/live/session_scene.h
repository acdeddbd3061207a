#pragma once
// What a task's scene id names, ready to simulate: a surgical scene (sim/surgery/), the one
// runtime of every live session and replay. The id says how it is read: surgical scene files live
// under "scenes/surgery/" (a liver or knee with probe, grasper, scalpel or scope bound to the
// station's devices); every other scene is a sim core scene (sim/scenes/*.json: the palpation
// block), made a surgical scene with a probe in each hand (make_block_surgery).
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "server/live/scene_library.h"
#include "sim/render/camera.h"
#include "sim/scene/scene.h"
#include "sim/surgery/scene_presets.h"

namespace incise::server::live {

class SessionScene {
 public:
  // Throws std::invalid_argument for a null setup.
  explicit SessionScene(std::shared_ptr<const sim::surgery::SurgicalSceneSetup> setup);
  // A sim core scene (tests and the palpation tasks), with a probe for each of two hands;
  // implicit, as the common case. Throws sim::SceneError as make_block_surgery does.
  SessionScene(const sim::Scene& block);  // NOLINT(google-explicit-constructor)

  const sim::surgery::SurgicalSceneSetup& setup() const { return *setup_; }
  const std::shared_ptr<const sim::surgery::SurgicalSceneSetup>& shared_setup() const {
    return setup_;
  }

 private:
  std::shared_ptr<const sim::surgery::SurgicalSceneSetup> setup_;
};

// Parses (and for a surgical scene meshes: about a second) the scene with this id and text.
// Throws sim::SceneError naming the JSON path of the first problem.
SessionScene load_session_scene(std::string_view id, std::string_view text);

// "" if a task's tools (tools[i] is held by device i) fit the scene, else why not: a surgical
// scene's tools are bound to devices, and the task must name each device's tool kind (e.g.
// "tools[0] is \"probe\" but the scene gives device 0 a scalpel"). The block's probes stand for
// any tool.
std::string tools_mismatch(const SessionScene& scene, const std::vector<std::string>& tools);

// The camera the live view starts with: the scene's "view" if it has one (the palpation block);
// otherwise a laparoscope held by the task (a scope on a device takes over frame by frame once it
// reports: scope_view): its tip kLaparoscopeDistance from the marked line's middle (the tissue's
// centre without a line), above and in front, looking at it with the light at its tip
// (render::Camera::headlight) and a 70-degree diagonal field of view at 4:3.
// A scene with portals (the knee) starts instead from kPortalEntry inside its first portal, looking
// along it.
render::Camera camera_for(const SessionScene& scene);
inline constexpr double kLaparoscopeDistance = 0.08;  // [m]
inline constexpr double kPortalEntry = 0.005;         // [m]

// The view from outside the body that an instructor may switch to: the scene's "view" if it has
// one; otherwise the whole tissue from above and in front, aimed halfway between the tissue's
// centre (of its bounding box) and the marked cut line's middle (the centre alone without a
// line), under the scene's directional light.
render::Camera outside_camera_for(const SessionScene& scene);

// What a scope sees in an image of this aspect (width / height): the eye at its tip, its field of
// view taken as the image's diagonal, its light at the tip.
render::Camera scope_view(const sim::surgery::ScopeCamera& scope, double aspect);

}  // namespace incise::server::live
