#include "server/live/scene_material.h"

#include <nlohmann/json.hpp>
#include <stdexcept>

#include "server/live/scene_library.h"

namespace incise::server::live {

std::string scene_with_material(std::string_view scene_id, std::string_view scene_text,
                                std::string_view constants, std::string_view model) {
  using nlohmann::json;
  if (scene_id.starts_with(kSurgicalScenePrefix)) {
    throw std::invalid_argument("a named material applies to sim core scenes, and \"" +
                                std::string(scene_id) + "\" is a surgical scene");
  }
  json scene = json::parse(scene_text, nullptr, false);
  const json material = json::parse(constants, nullptr, false);
  if (!scene.is_object() || !scene.contains("material") || !scene["material"].is_object()) {
    throw std::invalid_argument("scene \"" + std::string(scene_id) + "\" has no material block");
  }
  if (!material.is_object() || !material.contains("material") ||
      !material["material"].is_object()) {
    throw std::invalid_argument("the material's constants are malformed");
  }
  const json scene_model = scene["material"].value("model", json("mss"));
  if (scene_model != json(model)) {
    throw std::invalid_argument("the material is for the \"" + std::string(model) +
                                "\" model, and scene \"" + std::string(scene_id) + "\" uses " +
                                scene_model.dump());
  }
  for (const char* key : {"E", "nu", "density", "damping"}) {
    const auto found = material["material"].find(key);
    if (found == material["material"].end() || !found->is_number()) {
      throw std::invalid_argument(std::string("the material's constants lack ") + key);
    }
    scene["material"][key] = *found;
  }
  // The springs' volume term was part of what was fitted: the material's, or none.
  if (model == "mss") {
    scene["material"]["volume_stiffness"] = material["material"].value("volume_stiffness", 0.0);
  }
  scene.erase("materials");
  if (material.contains("materials")) scene["materials"] = material["materials"];
  return scene.dump(2);
}

}  // namespace incise::server::live
