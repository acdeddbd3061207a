#include "server/calibration_scenes.h"

#include <algorithm>
#include <cstdio>
#include <exception>
#include <optional>
#include <set>

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

}  // namespace

const std::vector<CalibrationScene>& calibration_scenes() {
  // The scenes are compiled in: parsed once, on first use.
  static const std::vector<CalibrationScene> scenes = [] {
    std::vector<CalibrationScene> out;
    for (const live::SceneSource& source : live::all_scenes()) {
      const auto scene = calibratable(source);
      if (!scene) continue;
      CalibrationScene entry;
      entry.id = source.id;
      entry.model = sim::material_model_name(scene->material.model);
      entry.per_node = scene->material.model == sim::MaterialModel::mass_spring &&
                       scene->material.volume_stiffness == 0;
      entry.has_example = live::find_example_data(source.id).has_value();
      const sim::Vec3 size = scene->mesh.box.size * 100;
      const sim::Vec3i cells = scene->mesh.box.cells;
      char title[160];
      std::snprintf(title, sizeof title, "%s: %s block %.3gx%.3gx%.3g cm, %dx%dx%d cells",
                    source.id.substr(source.id.rfind('/') + 1).data(), entry.model.c_str(),
                    size.x(), size.y(), size.z(), cells.x(), cells.y(), cells.z());
      entry.title = title;
      out.push_back(std::move(entry));
    }
    return out;
  }();
  return scenes;
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

void check_job_size(const CalibrationSetup& setup, bool per_node, std::string_view method) {
  std::size_t samples = 0;
  for (const auto& c : setup.data.contacts)
    samples += c.samples.size();
  const std::size_t contacts = setup.data.contacts.size();
  if (contacts > kMaxJobContacts) {
    throw CalibrationError("data: " + std::to_string(contacts) + " contacts, at most " +
                           std::to_string(kMaxJobContacts));
  }
  if (samples > kMaxJobSamples) {
    throw CalibrationError("data: " + std::to_string(samples) + " samples, at most " +
                           std::to_string(kMaxJobSamples));
  }
  // Parameters: a modulus per node, or per label (and nu with it for the FEM models).
  std::set<int> labels;
  for (Eigen::Index t = 0; t < setup.mesh.labels.size(); ++t)
    labels.insert(setup.mesh.labels[t]);
  const bool fem = setup.scene.material.model != sim::MaterialModel::mass_spring;
  const double parameters =
      per_node ? setup.mesh.num_nodes()
               : static_cast<double>(std::max<std::size_t>(labels.size(), 1)) * (fem ? 2 : 1);
  // Residuals: three per sample, and per node a prior term per spring (about 7 per node).
  const double residuals = 3.0 * static_cast<double>(samples) + (per_node ? 7.0 * parameters : 0);
  if (method == "lm" && residuals * parameters > kMaxJacobianEntries) {
    throw CalibrationError("data: lm's Jacobian would hold " +
                           std::to_string(static_cast<long long>(residuals * parameters)) +
                           " numbers (at most 25000000): fewer samples, per label, or ga");
  }
  if (method == "cmaes" && parameters > kMaxCmaesParameters) {
    throw CalibrationError("per: cmaes fits at most " + std::to_string(kMaxCmaesParameters) +
                           " parameters, and this scene has " +
                           std::to_string(static_cast<long long>(parameters)) +
                           " nodes: per label, or lm");
  }
}

}  // namespace incise::server
