#include "server/live/session_scene.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "sim/io/scene_json.h"
#include "sim/surgery/scene_file.h"

namespace incise::server::live {

SessionScene::SessionScene(std::shared_ptr<const sim::surgery::SurgicalSceneSetup> setup)
    : setup_(std::move(setup)) {
  if (!setup_) throw std::invalid_argument("a session scene needs a scene");
}

SessionScene::SessionScene(const sim::Scene& block)
    : setup_(std::make_shared<const sim::surgery::SurgicalSceneSetup>(
          sim::surgery::make_block_surgery(block))) {}

SessionScene load_session_scene(std::string_view id, std::string_view text) {
  if (id.starts_with(kSurgicalScenePrefix)) {
    return SessionScene(std::make_shared<const sim::surgery::SurgicalSceneSetup>(
        sim::surgery::parse_surgical_scene(text)));
  }
  return SessionScene(sim::parse_scene_text(text));
}

std::string tools_mismatch(const SessionScene& scene, const std::vector<std::string>& tools) {
  const sim::surgery::SurgicalSceneSetup& setup = scene.setup();
  if (setup.tools_stand_for_any) return "";
  for (std::size_t i = 0; i < tools.size(); ++i) {
    std::vector<std::string_view> held;
    for (const auto& t : setup.spec.tools) {
      if (t.device == static_cast<int>(i)) held.push_back(sim::surgery::to_string(t.kind));
    }
    if (std::find(held.begin(), held.end(), tools[i]) != held.end()) continue;
    std::string what = "tools[" + std::to_string(i) + "] is \"" + tools[i] + "\" but the scene ";
    if (held.empty()) return what + "has no tool on device " + std::to_string(i);
    what += "gives device " + std::to_string(i) + " a";
    for (std::size_t k = 0; k < held.size(); ++k)
      what += std::string(k == 0 ? " " : " and a ") + std::string(held[k]);
    return what;
  }
  return "";
}

namespace {

render::Camera with_clip_planes(render::Camera camera) {
  const double distance = (camera.eye - camera.target).norm();
  camera.near_m = std::max(1e-3, distance / 100);
  camera.far_m = distance * 10;
  return camera;
}

}  // namespace

namespace {

// The vertical field of view [deg] of an image of this aspect whose diagonal spans diagonal_deg.
double vertical_fov(double diagonal_deg, double aspect) {
  const double half = std::tan(diagonal_deg * std::numbers::pi / 360);
  return 360 / std::numbers::pi * std::atan(half / std::sqrt(1 + aspect * aspect));
}

// An endoscope's light reaches about this far [m] (render::Camera::light_falloff_m).
constexpr double kScopeLightFalloff = 0.08;
constexpr double kScopeFieldOfView = 70;  // diagonal [deg]

}  // namespace

render::Camera scope_view(const sim::surgery::ScopeCamera& scope, double aspect) {
  render::Camera camera;
  camera.eye = scope.eye;
  camera.target = scope.eye + scope.forward;
  camera.up = scope.up;
  camera.fov_y_deg = vertical_fov(scope.field_of_view_degrees, aspect);
  camera.near_m = 0.002;
  camera.far_m = 1.0;
  camera.headlight = true;
  camera.light_falloff_m = kScopeLightFalloff;
  return camera;
}

render::Camera camera_for(const SessionScene& scene) {
  const sim::surgery::SurgicalSceneSetup& setup = scene.setup();
  if (setup.view) return outside_camera_for(scene);
  const sim::Points& rest = setup.spec.tissue.rest;
  sim::Vec3 target = 0.5 * (rest.colwise().minCoeff() + rest.colwise().maxCoeff()).transpose();
  if (!setup.cut_target.empty()) {
    target = 0.5 * (setup.cut_target.front() + setup.cut_target.back());
  }
  sim::surgery::ScopeCamera scope;
  scope.eye = target + kLaparoscopeDistance * sim::Vec3(0, -0.5, 0.8).normalized();
  if (!setup.portals.empty()) {
    // A joint: until its arthroscope reports, the view from just inside the first portal (the
    // scope's), inside the capsule rather than outside it.
    const sim::Portal& portal = setup.portals.front();
    scope.eye = portal.position + kPortalEntry * portal.direction;
    target = scope.eye + portal.direction;
  }
  scope.forward = (target - scope.eye).normalized();
  scope.up = (sim::Vec3::UnitZ() - scope.forward.z() * scope.forward).normalized();
  scope.field_of_view_degrees = kScopeFieldOfView;
  return scope_view(scope, 4.0 / 3.0);
}

render::Camera outside_camera_for(const SessionScene& scene) {
  render::Camera camera;
  const sim::surgery::SurgicalSceneSetup& setup = scene.setup();
  if (const auto& view = setup.view) {
    camera.eye = view->eye;
    camera.target = view->target;
    camera.up = view->up;
    camera.fov_y_deg = view->fov_y_deg;
    return with_clip_planes(camera);
  }
  const sim::Points& rest = setup.spec.tissue.rest;
  const sim::Vec3 low = rest.colwise().minCoeff().transpose();
  const sim::Vec3 high = rest.colwise().maxCoeff().transpose();
  // Halfway between the tissue's centre and the marked line's middle (if it has one): the
  // line near the middle of the picture, the whole organ in view, from above and a little in
  // front as a laparoscope sees it.
  sim::Vec3 target = 0.5 * (low + high);
  if (!setup.cut_target.empty()) {
    target = 0.5 * (target + 0.5 * (setup.cut_target.front() + setup.cut_target.back()));
  }
  const double extent = (high - low).norm();
  camera.target = target;
  camera.eye = target + extent * sim::Vec3(0, -0.5, 0.8);
  camera.up = sim::Vec3::UnitZ();
  camera.fov_y_deg = 45;
  return with_clip_planes(camera);
}

}  // namespace incise::server::live
