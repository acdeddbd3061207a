#include "sim/surgery/scene_file.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>

#include "sim/io/json_object_reader.h"
#include "sim/scene/scene_validation.h"

namespace incise::sim::surgery {
namespace {

using nlohmann::json;

constexpr Real kInfinity = std::numeric_limits<Real>::infinity();
constexpr int kMaxDevices = 16;  // a station has a handful of devices; more is a typo

// "a, b, c" of a list of names.
template <typename Names>
std::string joined(const Names& names) {
  std::string text;
  for (const auto& name : names)
    text += (text.empty() ? "" : ", ") + std::string(name);
  return text;
}

// value in (lo, hi) with either end closed on request, else SceneError at path.
void check_range(const std::string& path, Real value, Real lo, bool lo_closed, Real hi,
                 bool hi_closed) {
  const bool above = lo_closed ? value >= lo : value > lo;
  const bool below = hi_closed ? value <= hi : value < hi;
  if (above && below) return;
  std::string range;
  if (hi == kInfinity) {
    range = std::string(lo_closed ? ">= " : "> ") + format_number(lo);
  } else {
    range = std::string("in ") + (lo_closed ? "[" : "(") + format_number(lo) + ", " +
            format_number(hi) + (hi_closed ? "]" : ")");
  }
  throw SceneError(path, "must be " + range + " (got " + format_number(value) + ")");
}

int read_count(const JsonObjectReader& object, std::string_view key, int lo, int hi) {
  const std::int64_t n = object.integer(key);
  if (n < lo || n > hi) {
    throw SceneError(object.path(key), "must be in [" + std::to_string(lo) + ", " +
                                           std::to_string(hi) + "] (got " + std::to_string(n) +
                                           ")");
  }
  return static_cast<int>(n);
}

// --- scene file ---

// The anatomy's own range checks (anatomy.h) say "<what>: <field> [unit] = v is outside [a, b]";
// their field names are the JSON keys, so the error can name the key's path without repeating
// the ranges here.
template <typename Check, typename Options>
void check_anatomy(Check check, const Options& options,
                   std::initializer_list<std::string_view> keys) {
  try {
    check(options);
  } catch (const std::invalid_argument& error) {
    std::string reason = error.what();
    const std::size_t colon = reason.find(": ");
    if (colon != std::string::npos) reason.erase(0, colon + 2);
    std::string path = "anatomy_options";
    for (const std::string_view key : keys) {
      if (reason.compare(0, key.size() + 1, std::string(key) + " ") == 0) {
        path = member_path(path, key);
      }
    }
    throw SceneError(path, reason);
  }
}

LiverOptions read_liver_options(const json& value, LiverOptions options) {
  const JsonObjectReader o(value, "anatomy_options",
                           {"centre", "length", "cell_size", "cut_length", "cut_points"});
  if (o.has("centre")) options.centre = o.vec3("centre");
  if (o.has("length")) options.length = o.number("length");
  if (o.has("cell_size")) options.cell_size = o.number("cell_size");
  if (o.has("cut_length")) options.cut_length = o.number("cut_length");
  if (o.has("cut_points")) options.cut_points = read_count(o, "cut_points", 2, 1000);
  check_anatomy(check_liver_options, options,
                {"centre", "length", "cell_size", "cut_length", "cut_points"});
  return options;
}

KneeOptions read_knee_options(const json& value, KneeOptions options) {
  const JsonObjectReader o(value, "anatomy_options",
                           {"voxel_size", "tissue_cell_size", "bone_facet_size", "flexion_deg"});
  if (o.has("voxel_size")) options.voxel_size = o.number("voxel_size");
  if (o.has("tissue_cell_size")) options.tissue_cell_size = o.number("tissue_cell_size");
  if (o.has("bone_facet_size")) options.bone_facet_size = o.number("bone_facet_size");
  if (o.has("flexion_deg")) options.flexion_deg = o.number("flexion_deg");
  check_anatomy(check_knee_options, options,
                {"voxel_size", "tissue_cell_size", "bone_facet_size", "flexion_deg"});
  return options;
}

void read_material(const json& value, const std::string& path, Material& material) {
  const JsonObjectReader o(value, path, {"model", "E", "nu", "density", "damping"});
  if (o.has("model")) {
    const std::string name = o.string("model");
    const std::optional<MaterialModel> model = material_model_named(name);
    if (!model) {
      throw SceneError(o.path("model"),
                       describe(json(name)) + " is not one of " + std::string(kMaterialModelNames));
    }
    material.model = *model;
  }
  if (o.has("E")) material.youngs_modulus = o.number("E");
  if (o.has("nu")) material.poisson_ratio = o.number("nu");
  if (o.has("density")) material.density = o.number("density");
  if (o.has("damping")) material.damping = o.number("damping");
  check_range(o.path("E"), material.youngs_modulus, 0, false, kInfinity, false);
  check_range(o.path("nu"), material.poisson_ratio, -1, false, 0.5, false);
  check_range(o.path("density"), material.density, 0, false, kInfinity, false);
  check_range(o.path("damping"), material.damping, 0, true, 1, true);
}

constexpr std::pair<const char*, ToolKind> kToolKinds[] = {
    {"probe", ToolKind::probe},
    {"grasper", ToolKind::grasper},
    {"scalpel", ToolKind::scalpel},
    {"scope", ToolKind::scope},
};

// Which kinds a setting belongs to (bit per ToolKind).
constexpr unsigned bit(ToolKind kind) {
  return 1u << static_cast<unsigned>(kind);
}
constexpr unsigned kAllKinds = 0xF;

struct ToolSetting {
  const char* key;
  unsigned kinds;
  Real& (*field)(ToolSpec&);
  Real lo;
  bool lo_closed;
  Real hi;  // excluded (every upper end is open)
};

// The settings a file may give a tool, their kinds and ranges (those SurgicalScene and the tools
// check). The probe's radius must exceed its allowed penetration per step (probe.h).
const ToolSetting kToolSettings[] = {
    {"shaft_length", kAllKinds, [](ToolSpec& t) -> Real& { return t.shaft_length; }, 0, false,
     kInfinity},
    {"shaft_radius", kAllKinds, [](ToolSpec& t) -> Real& { return t.shaft_radius; }, 0, false,
     kInfinity},
    {"radius", bit(ToolKind::probe), [](ToolSpec& t) -> Real& { return t.probe.radius; },
     tools::ProbeSettings{}.allowed_penetration, false, kInfinity},
    {"coupling_stiffness", bit(ToolKind::probe) | bit(ToolKind::scope),
     [](ToolSpec& t) -> Real& { return t.probe.coupling_stiffness; }, 0, false, kInfinity},
    {"max_force", bit(ToolKind::probe) | bit(ToolKind::scope),
     [](ToolSpec& t) -> Real& { return t.probe.max_force; }, 0, false, kInfinity},
    {"tear_force", bit(ToolKind::grasper), [](ToolSpec& t) -> Real& { return t.grasp.tear_force; },
     0, false, kInfinity},
    {"jaw_length", bit(ToolKind::grasper), [](ToolSpec& t) -> Real& { return t.grasp.jaw_length; },
     0, false, kInfinity},
    {"reach", bit(ToolKind::grasper), [](ToolSpec& t) -> Real& { return t.grasp.reach; }, 0, true,
     kInfinity},
    {"max_jaw_angle", bit(ToolKind::grasper), [](ToolSpec& t) -> Real& { return t.max_jaw_angle; },
     0, false, std::numbers::pi},
    {"blade_length", bit(ToolKind::scalpel), [](ToolSpec& t) -> Real& { return t.blade_length; }, 0,
     false, kInfinity},
    {"view_angle_degrees", bit(ToolKind::scope),
     [](ToolSpec& t) -> Real& { return t.view_angle_degrees; }, 0, true, 90},
    {"field_of_view_degrees", bit(ToolKind::scope),
     [](ToolSpec& t) -> Real& { return t.field_of_view_degrees; }, 0, false, 180},
};

std::string kinds_of(unsigned kinds) {
  std::vector<std::string> names;
  for (const auto& [name, kind] : kToolKinds) {
    if ((kinds & bit(kind)) != 0) names.emplace_back(name);
  }
  return joined(names);
}

ToolSpec read_tool(const json& value, const std::string& path,
                   const std::vector<ToolSpec>& preset_tools) {
  const JsonObjectReader o(
      value, path,
      {"kind", "device", "shaft_length", "shaft_radius", "radius", "coupling_stiffness",
       "max_force", "tear_force", "jaw_length", "reach", "max_jaw_angle", "blade_length",
       "view_angle_degrees", "field_of_view_degrees"});
  const std::string name = o.string("kind");
  const auto* found = std::find_if(std::begin(kToolKinds), std::end(kToolKinds),
                                   [&](const auto& k) { return name == k.first; });
  if (found == std::end(kToolKinds)) {
    throw SceneError(o.path("kind"),
                     describe(json(name)) + " is not one of " + kinds_of(kAllKinds));
  }
  const ToolKind kind = found->second;
  const auto preset = std::find_if(preset_tools.begin(), preset_tools.end(),
                                   [&](const ToolSpec& t) { return t.kind == kind; });
  ToolSpec tool = preset != preset_tools.end() ? *preset : ToolSpec{};
  tool.kind = kind;
  tool.device = read_count(o, "device", 0, kMaxDevices - 1);
  for (const ToolSetting& s : kToolSettings) {
    if (!o.has(s.key)) continue;
    if ((s.kinds & bit(kind)) == 0) {
      throw SceneError(o.path(s.key),
                       "is a setting of " + kinds_of(s.kinds) + ", not of a " + name);
    }
    const Real v = o.number(s.key);
    check_range(o.path(s.key), v, s.lo, s.lo_closed, s.hi, false);
    s.field(tool) = v;
  }
  return tool;
}

std::vector<ToolSpec> read_tools(const JsonObjectReader& root,
                                 const std::vector<ToolSpec>& preset_tools) {
  const json& array = root.required("tools");
  if (!array.is_array()) {
    throw SceneError("tools", "must be an array (got " + describe(array) + ")");
  }
  std::vector<ToolSpec> tools;
  for (std::size_t k = 0; k < array.size(); ++k)
    tools.push_back(read_tool(array[k], element_path("tools", k), preset_tools));
  return tools;
}

void read_damage(const json& value, Real& strain_threshold, Real& target_half_width) {
  const JsonObjectReader o(value, "damage", {"strain_threshold", "target_half_width"});
  if (o.has("strain_threshold")) strain_threshold = o.number("strain_threshold");
  if (o.has("target_half_width")) target_half_width = o.number("target_half_width");
  check_range(o.path("strain_threshold"), strain_threshold, 0, false, kInfinity, false);
  check_range(o.path("target_half_width"), target_half_width, 0, false, kInfinity, false);
}

void read_adaptivity(const json& value, AdaptivitySpec& a) {
  const JsonObjectReader o(value, "adaptivity",
                           {"enabled", "edge_length", "radius", "coarsen_after", "max_splits"});
  if (o.has("enabled")) a.enabled = o.boolean("enabled");
  if (o.has("edge_length")) a.edge_length = o.number("edge_length");
  if (o.has("radius")) a.radius = o.number("radius");
  if (o.has("coarsen_after")) a.coarsen_after = o.number("coarsen_after");
  if (o.has("max_splits")) {
    a.max_splits = read_count(o, "max_splits", 1, std::numeric_limits<int>::max());
  }
  check_range(o.path("edge_length"), a.edge_length, 0, false, kInfinity, false);
  check_range(o.path("radius"), a.radius, 0, false, kInfinity, false);
  check_range(o.path("coarsen_after"), a.coarsen_after, 0, true, kInfinity, false);
}

// The scene-kind specific members, read into options (LiverSceneOptions or KneeSceneOptions).
template <typename SceneOptions>
void read_common(const JsonObjectReader& root, SceneOptions& options) {
  if (root.has("tools")) options.tools = read_tools(root, SceneOptions::default_tools());
  if (root.has("ambient_damping")) {
    options.ambient_damping = root.number("ambient_damping");
    check_range(root.path("ambient_damping"), options.ambient_damping, 0, true, kInfinity, false);
  }
  if (root.has("adaptivity")) read_adaptivity(root.required("adaptivity"), options.adaptivity);
  if (root.has("damage")) {
    read_damage(root.required("damage"), options.strain_threshold, options.target_half_width);
  }
}

}  // namespace

SurgicalSceneFile parse_surgical_scene_file(const json& value) {
  if (!value.is_object()) {
    throw SceneError("", "the scene must be a JSON object (got " + describe(value) + ")");
  }
  const JsonObjectReader root(
      value, "",
      {"description", "anatomy", "anatomy_options", "materials", "ambient_damping", "adaptivity",
       "operational_radius", "tools", "damage", "solver"});
  if (root.has("description")) (void)root.string("description");
  SurgicalSceneFile file;
  const std::string anatomy = root.string("anatomy");
  if (anatomy == "liver") {
    file.anatomy = Anatomy::liver;
  } else if (anatomy == "knee") {
    file.anatomy = Anatomy::knee;
  } else {
    throw SceneError("anatomy", describe(json(anatomy)) + " is not one of liver, knee");
  }
  if (file.anatomy == Anatomy::liver) {
    LiverSceneOptions& o = file.liver;
    if (root.has("anatomy_options")) {
      o.anatomy = read_liver_options(root.required("anatomy_options"), o.anatomy);
    }
    if (root.has("materials")) {
      const JsonObjectReader m(root.required("materials"), "materials", {"liver"});
      if (m.has("liver")) read_material(m.required("liver"), m.path("liver"), o.liver);
    }
    read_common(root, o);
    if (root.has("operational_radius")) {
      o.operational_radius = root.number("operational_radius");
      check_range(root.path("operational_radius"), o.operational_radius, 0, true, kInfinity, false);
    }
  } else {
    KneeSceneOptions& o = file.knee;
    if (root.has("anatomy_options")) {
      o.anatomy = read_knee_options(root.required("anatomy_options"), o.anatomy);
    }
    if (root.has("materials")) {
      const JsonObjectReader m(root.required("materials"), "materials", {"meniscus", "ligament"});
      if (m.has("meniscus")) read_material(m.required("meniscus"), m.path("meniscus"), o.meniscus);
      if (m.has("ligament")) read_material(m.required("ligament"), m.path("ligament"), o.ligament);
    }
    if (root.has("operational_radius")) {
      throw SceneError("operational_radius", "is a setting of the liver, not of the knee");
    }
    read_common(root, o);
  }
  if (root.has("solver")) {
    const JsonObjectReader s(root.required("solver"), "solver", {"cut_every", "damage_every"});
    const int max = std::numeric_limits<int>::max();
    if (s.has("cut_every")) file.cut_every = read_count(s, "cut_every", 1, max);
    if (s.has("damage_every")) file.damage_every = read_count(s, "damage_every", 1, max);
  }
  return file;
}

SurgicalSceneSetup build_surgical_scene(const SurgicalSceneFile& file) {
  SurgicalSceneSetup setup = file.anatomy == Anatomy::liver ? make_liver_surgery(file.liver)
                                                            : make_knee_surgery(file.knee);
  setup.spec.cut_every = file.cut_every;
  setup.spec.damage_every = file.damage_every;
  return setup;
}

SurgicalSceneSetup parse_surgical_scene(std::string_view text) {
  return build_surgical_scene(parse_surgical_scene_file(parse_json_text(text)));
}

SurgicalSceneSetup read_surgical_scene(const std::filesystem::path& file) {
  return parse_surgical_scene(read_text_file(file));
}

// --- script ---

namespace {

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
    for (const auto& [name, point] : ends) {
      const bool named =
          std::any_of(places.begin(), places.end(), [&](const Place& p) { return p.name == name; });
      if (!named) places.push_back({name, point, std::nullopt});
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
      value, path, {"t", "tip", "at", "offset", "direction", "towards", "along", "advance", "jaw"});
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
  const int given = int(o.has("direction")) + int(o.has("towards")) + int(o.has("along"));
  if (given > 1) {
    throw SceneError(path, "has more than one of \"direction\", \"towards\", \"along\"");
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

ToolInput sample_track(const DeviceTrack& track, Real t) {
  const std::vector<Keyframe>& keys = track.keyframes;
  const auto next = std::upper_bound(keys.begin(), keys.end(), t,
                                     [](Real time, const Keyframe& k) { return time < k.t; });
  Vec3 tip, direction;
  Real jaw = 0;
  if (next == keys.begin() || next == keys.end()) {
    const Keyframe& held = next == keys.begin() ? keys.front() : keys.back();
    tip = held.tip;
    direction = held.direction;
    jaw = held.jaw;
  } else {
    const Keyframe& a = *(next - 1);
    const Keyframe& b = *next;
    const Real s = (t - a.t) / (b.t - a.t);
    tip = a.tip + s * (b.tip - a.tip);
    direction = ((1 - s) * a.direction + s * b.direction).normalized();
    jaw = a.jaw + s * (b.jaw - a.jaw);
  }
  ToolInput input;
  input.tip = tip;
  input.orientation = Eigen::Quaternion<Real>::FromTwoVectors(Vec3::UnitZ(), direction);
  input.jaw = jaw;
  return input;
}

void sample_script(const ToolScript& script, Real t, std::vector<ToolInput>& inputs) {
  inputs.resize(script.devices.size());
  for (std::size_t d = 0; d < script.devices.size(); ++d)
    inputs[d] = sample_track(script.devices[d], t);
}

}  // namespace incise::sim::surgery
