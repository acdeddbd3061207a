#include "server/calibration_scenes.h"

#include <cstdio>
#include <exception>
#include <optional>

#include "server/live/scene_library.h"
#include "sim/calibrate/calibration.h"
#include "sim/io/scene_json.h"
#include "sim/mesh/box_mesher.h"

namespace incise::server {
namespace {

using sim::calibrate::CalibrationError;

// The scene's calibration view, or nullopt when calibration cannot use it.
std::optional<sim::Scene> calibratable(const live::SceneSource& source) {
  if (source.id.starts_with(live::kSurgicalScenePrefix)) return std::nullopt;
  try {
    sim::Scene scene = sim::parse_scene_text(source.text);
    if (scene.mesh.source != sim::MeshSource::box || scene.adaptivity) return std::nullopt;
    return scene;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

std::string_view model_name(sim::MaterialModel model) {
  for (const std::string_view name : {"mss", "linear", "corotational", "corotational_polar",
                                      "corotational_nodal_pressure", "stvk", "neohookean"}) {
    if (sim::material_model_named(name) == model) return name;
  }
  return "mss";
}

}  // namespace

std::vector<CalibrationScene> calibration_scenes() {
  std::vector<CalibrationScene> out;
  for (const live::SceneSource& source : live::all_scenes()) {
    const auto scene = calibratable(source);
    if (!scene) continue;
    CalibrationScene entry;
    entry.id = source.id;
    entry.model = model_name(scene->material.model);
    entry.per_node = scene->material.model == sim::MaterialModel::mass_spring &&
                     scene->material.volume_stiffness == 0;
    entry.has_example = live::find_example_data(source.id).has_value();
    const sim::Vec3 size = scene->mesh.box.size * 100;
    const sim::Vec3i cells = scene->mesh.box.cells;
    char title[160];
    std::snprintf(title, sizeof title, "%s: %s block %.3gx%.3gx%.3g cm, %dx%dx%d cells",
                  source.id.substr(source.id.rfind('/') + 1).data(), entry.model.c_str(), size.x(),
                  size.y(), size.z(), cells.x(), cells.y(), cells.z());
    entry.title = title;
    out.push_back(std::move(entry));
  }
  return out;
}

CalibrationSetup calibration_setup(std::string_view scene_id, std::string_view csv) {
  const auto source = live::find_scene(scene_id);
  const auto scene = source ? calibratable(*source) : std::nullopt;
  if (!scene) {
    throw CalibrationError("scene: \"" + std::string(scene_id) +
                           "\" is not a scene this server can calibrate");
  }
  CalibrationSetup setup;
  setup.scene = *scene;
  setup.mesh = sim::make_box_mesh(scene->mesh.box.size, scene->mesh.box.cells.cast<int>());
  try {
    setup.data = sim::calibrate::parse_probe_csv(csv);
    // Contact, fixed nodes and motion, before anything is queued.
    sim::calibrate::check_probe_data(setup.scene, setup.mesh, setup.data);
  } catch (const CalibrationError& e) {
    throw CalibrationError(std::string("data: ") + e.what());
  }
  return setup;
}

}  // namespace incise::server
