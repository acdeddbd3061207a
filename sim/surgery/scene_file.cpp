// A surgical scene file's JSON: the anatomy and its options, materials, tools, damage,
// adaptivity and solver settings, read into the preset's options and built.
#include "sim/surgery/scene_file.h"

#include <algorithm>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sim/io/json_object_reader.h"
#include "sim/scene/scene_validation.h"
#include "sim/surgery/scene_file_checks.h"

namespace incise::sim::surgery {
namespace {

using nlohmann::json;

constexpr int kMaxDevices = 16;  // a station has a handful of devices; more is a typo

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

// A tissue's material and its toughness [J/m^2] (the scalpel's cutting resistance).
void read_material(const json& value, const std::string& path, Material& material,
                   Real& toughness) {
  const JsonObjectReader o(value, path, {"model", "E", "nu", "density", "damping", "toughness"});
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
  if (o.has("toughness")) toughness = o.number("toughness");
  check_range(o.path("E"), material.youngs_modulus, 0, false, kInfinity, false);
  check_range(o.path("nu"), material.poisson_ratio, -1, false, 0.5, false);
  check_range(o.path("density"), material.density, 0, false, kInfinity, false);
  check_range(o.path("damping"), material.damping, 0, true, 1, true);
  check_range(o.path("toughness"), toughness, 0, true, kInfinity, false);
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
      if (m.has("liver")) {
        read_material(m.required("liver"), m.path("liver"), o.liver, o.liver_toughness);
      }
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
      if (m.has("meniscus")) {
        read_material(m.required("meniscus"), m.path("meniscus"), o.meniscus, o.meniscus_toughness);
      }
      if (m.has("ligament")) {
        read_material(m.required("ligament"), m.path("ligament"), o.ligament, o.ligament_toughness);
      }
    }
    if (root.has("operational_radius")) {
      throw SceneError("operational_radius", "is a setting of the liver, not of the knee");
    }
    read_common(root, o);
  }
  if (root.has("solver")) {
    const JsonObjectReader s(root.required("solver"), "solver",
                             {"cut_every", "damage_every", "time_step"});
    const int max = std::numeric_limits<int>::max();
    if (s.has("cut_every")) file.cut_every = read_count(s, "cut_every", 1, max);
    if (s.has("damage_every")) file.damage_every = read_count(s, "damage_every", 1, max);
    if (s.has("time_step")) {
      Real& step = file.anatomy == Anatomy::liver ? file.liver.time_step : file.knee.time_step;
      step = s.number("time_step");
      check_range(s.path("time_step"), step, 0, true, 0.01, true);
    }
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

}  // namespace incise::sim::surgery
