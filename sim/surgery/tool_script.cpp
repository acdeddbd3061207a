// A tool script's JSON: per device a track of keyframes, their places resolved in the scene.
#include <algorithm>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sim/io/json_object_reader.h"
#include "sim/scene/scene_validation.h"
#include "sim/surgery/scene_file_checks.h"
#include "sim/surgery/tool_script.h"

namespace incise::sim::surgery {
namespace {

using nlohmann::json;

// A named point of the scene a keyframe may refer to; portals also have a direction.
struct Place {
  std::string name;
  Vec3 position;
  std::optional<Vec3> direction;
};

std::vector<Place> places_of(const SurgicalSceneSetup& scene) {
  std::vector<Place> places;
  for (const Landmark& l : scene.landmarks)
    places.push_back({l.name, l.position, std::nullopt});
  for (const Portal& p : scene.portals)
    places.push_back({p.name, p.position, p.direction});
  if (!scene.cut_target.empty()) {
    const std::pair<const char*, Vec3> ends[] = {{"cut_start", scene.cut_target.front()},
                                                 {"cut_end", scene.cut_target.back()}};
    for (const auto& end : ends) {
      const bool named = std::any_of(places.begin(), places.end(),
                                     [&](const Place& p) { return p.name == end.first; });
      if (!named) places.push_back({end.first, end.second, std::nullopt});
    }
  }
  return places;
}

const Place& find_place(const std::vector<Place>& places, const JsonObjectReader& o,
                        std::string_view key, const std::string& scene, bool portal) {
  const std::string name = o.string(key);
  std::vector<std::string> names;
  for (const Place& p : places) {
    if (portal && !p.direction) continue;
    if (p.name == name) return p;
    names.push_back(p.name);
  }
  throw SceneError(o.path(key), describe(json(name)) + " is not a " +
                                    (portal ? "portal" : "place") + " of the " + scene +
                                    " scene (one of: " + joined(names) + ")");
}

Keyframe read_keyframe(const json& value, const std::string& path, const Keyframe* previous,
                       Real duration, const std::vector<Place>& places, const std::string& scene) {
  const JsonObjectReader o(
      value, path,
      {"t", "tip", "at", "offset", "direction", "towards", "from", "along", "advance", "jaw"});
  Keyframe k;
  k.t = o.number("t");
  check_range(o.path("t"), k.t, 0, true, duration, true);
  if (previous != nullptr && !(k.t > previous->t)) {
    throw SceneError(o.path("t"), "must be after the previous keyframe's (" +
                                      format_number(previous->t) + ") (got " + format_number(k.t) +
                                      ")");
  }
  if (o.has("tip") == o.has("at")) {
    throw SceneError(
        path, o.has("tip") ? "has both \"tip\" and \"at\" (give one)" : "needs \"tip\" or \"at\"");
  }
  if (o.has("offset") && !o.has("at")) {
    throw SceneError(o.path("offset"), "belongs to \"at\" (a \"tip\" is already a point)");
  }
  const Vec3 base = o.has("tip") ? o.vec3("tip")
                                 : find_place(places, o, "at", scene, false).position +
                                       (o.has("offset") ? o.vec3("offset") : Vec3::Zero());
  const int given =
      int(o.has("direction")) + int(o.has("towards")) + int(o.has("from")) + int(o.has("along"));
  if (given > 1) {
    throw SceneError(path, "has more than one of \"direction\", \"towards\", \"from\", \"along\"");
  }
  std::string direction_path = path;
  k.direction = previous != nullptr ? previous->direction : Vec3(-Vec3::UnitZ());
  if (o.has("direction")) {
    direction_path = o.path("direction");
    const Vec3 d = o.vec3("direction");
    if (!(d.norm() > 0)) throw SceneError(direction_path, "must not be zero");
    k.direction = d.normalized();
  } else if (o.has("towards")) {
    direction_path = o.path("towards");
    const Vec3 d = find_place(places, o, "towards", scene, false).position - base;
    if (!(d.norm() > 1e-9)) throw SceneError(direction_path, "is where the tip is");
    k.direction = d.normalized();
  } else if (o.has("from")) {
    direction_path = o.path("from");
    const Vec3 d = base - find_place(places, o, "from", scene, false).position;
    if (!(d.norm() > 1e-9)) throw SceneError(direction_path, "is where the tip is");
    k.direction = d.normalized();
  } else if (o.has("along")) {
    direction_path = o.path("along");
    k.direction = *find_place(places, o, "along", scene, true).direction;
  }
  // Normalised lerp between opposite directions passes through zero: no direction halfway.
  if (previous != nullptr && k.direction.dot(previous->direction) < -1 + 1e-12) {
    throw SceneError(direction_path,
                     "turns the tool round from the previous keyframe's direction (undefined "
                     "halfway; add a keyframe between)");
  }
  k.tip = base + (o.has("advance") ? o.number("advance") : 0) * k.direction;
  k.jaw = previous != nullptr ? previous->jaw : 1;
  if (o.has("jaw")) {
    k.jaw = o.number("jaw");
    check_range(o.path("jaw"), k.jaw, 0, true, 1, true);
  }
  return k;
}

}  // namespace

ToolScript parse_tool_script(const json& value, const SurgicalSceneSetup& scene) {
  if (!value.is_object()) {
    throw SceneError("", "the script must be a JSON object (got " + describe(value) + ")");
  }
  const JsonObjectReader root(value, "", {"description", "duration", "devices"});
  if (root.has("description")) (void)root.string("description");
  ToolScript script;
  script.duration = root.number("duration");
  check_range("duration", script.duration, 0, false, kInfinity, false);
  const json& devices = root.required("devices");
  if (!devices.is_array() || devices.empty()) {
    throw SceneError("devices", "must be a non-empty array (got " + describe(devices) + ")");
  }
  const std::vector<Place> places = places_of(scene);
  for (std::size_t d = 0; d < devices.size(); ++d) {
    const std::string path = element_path("devices", d);
    const JsonObjectReader device(devices[d], path, {"keyframes"});
    const bool used = std::any_of(scene.spec.tools.begin(), scene.spec.tools.end(),
                                  [&](const ToolSpec& t) { return t.device == int(d); });
    if (!used) {
      throw SceneError(path,
                       "no tool of the " + scene.name + " scene is on device " + std::to_string(d));
    }
    const json& keyframes = device.required("keyframes");
    const std::string keyframes_path = device.path("keyframes");
    if (!keyframes.is_array() || keyframes.empty()) {
      throw SceneError(keyframes_path,
                       "must be a non-empty array (got " + describe(keyframes) + ")");
    }
    DeviceTrack track;
    for (std::size_t k = 0; k < keyframes.size(); ++k) {
      const Keyframe* previous = track.keyframes.empty() ? nullptr : &track.keyframes.back();
      track.keyframes.push_back(read_keyframe(keyframes[k], element_path(keyframes_path, k),
                                              previous, script.duration, places, scene.name));
    }
    script.devices.push_back(std::move(track));
  }
  return script;
}

ToolScript parse_tool_script_text(std::string_view text, const SurgicalSceneSetup& scene) {
  return parse_tool_script(parse_json_text(text), scene);
}

ToolScript read_tool_script(const std::filesystem::path& file, const SurgicalSceneSetup& scene) {
  return parse_tool_script_text(read_text_file(file), scene);
}

}  // namespace incise::sim::surgery
