// A surgical scene's spec validation: every field in its range, named in the error.
#include "sim/surgery/surgical_scene_validation.h"

#include <cmath>
#include <cstddef>
#include <numbers>
#include <stdexcept>
#include <string>

#include "sim/tools/probe.h"

namespace incise::sim::surgery {

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("surgical scene: " + what);
}

namespace {

std::string field(std::size_t k, const char* name) {
  return "tools[" + std::to_string(k) + "]." + name;
}

}  // namespace

void validate(const SurgicalSceneSpec& spec) {
  require(spec.dt > 0 && std::isfinite(spec.dt), "dt must be > 0");
  require(spec.gravity.allFinite(), "gravity must be finite");
  require(spec.bone_stiffness > 0 && std::isfinite(spec.bone_stiffness),
          "bone_stiffness must be > 0");
  require(spec.wave_speed > 0 && std::isfinite(spec.wave_speed), "wave_speed must be > 0");
  require(spec.damping_time >= 0 && std::isfinite(spec.damping_time), "damping_time must be >= 0");
  require(spec.ambient_damping >= 0 && std::isfinite(spec.ambient_damping),
          "ambient_damping must be >= 0");
  require(spec.cut_every >= 1, "cut_every must be >= 1");
  require(spec.damage_every >= 1, "damage_every must be >= 1");
  for (std::size_t k = 0; k < spec.toughness.size(); ++k) {
    const LabelToughness& t = spec.toughness[k];
    const std::string name = "toughness[" + std::to_string(k) + "]";
    require(t.toughness >= 0 && std::isfinite(t.toughness), name + ".toughness must be >= 0");
    for (std::size_t j = 0; j < k; ++j) {
      require(spec.toughness[j].label != t.label,
              name + ".label " + std::to_string(t.label) + " is listed twice");
    }
  }
  require(spec.default_toughness >= 0 && std::isfinite(spec.default_toughness),
          "default_toughness must be >= 0");
  require(spec.cutting.ramp_speed > 0 && std::isfinite(spec.cutting.ramp_speed),
          "cutting.ramp_speed must be > 0");
  require(spec.cutting.max_force > 0 && std::isfinite(spec.cutting.max_force),
          "cutting.max_force must be > 0");
  const AdaptivitySpec& a = spec.adaptivity;
  require(a.edge_length > 0 && std::isfinite(a.edge_length), "adaptivity.edge_length must be > 0");
  require(a.radius > 0 && std::isfinite(a.radius), "adaptivity.radius must be > 0");
  require(a.coarsen_after >= 0 && std::isfinite(a.coarsen_after),
          "adaptivity.coarsen_after must be >= 0");
  require(a.max_splits >= 1, "adaptivity.max_splits must be >= 1");
  if (spec.far_field.enabled) {
    require(spec.far_field.centre.allFinite(), "far_field.centre must be finite");
    require(spec.far_field.radius > 0 && std::isfinite(spec.far_field.radius),
            "far_field.radius must be > 0");
  }
  for (std::size_t k = 0; k < spec.tools.size(); ++k) {
    const ToolSpec& t = spec.tools[k];
    require(t.device >= 0, field(k, "device") + " must be >= 0");
    require(t.shaft_length > 0 && t.shaft_radius > 0,
            field(k, "shaft") + " length and radius must be > 0");
    require(t.max_jaw_angle > 0 && t.max_jaw_angle < std::numbers::pi,
            field(k, "max_jaw_angle") + " must be in (0, pi)");
    require(t.blade_length > 0, field(k, "blade_length") + " must be > 0");
    require(t.view_angle_degrees >= 0 && t.view_angle_degrees < 90,
            field(k, "view_angle_degrees") + " must be in [0, 90)");
    require(t.field_of_view_degrees > 0 && t.field_of_view_degrees < 180,
            field(k, "field_of_view_degrees") + " must be in (0, 180)");
    if (t.kind == ToolKind::probe || t.kind == ToolKind::scope) {
      // The tip's settings now, not when the tool first comes clear of the tissue (its probe is
      // made then: surgical_scene_tool.h).
      tools::ProbeSettings settings = t.probe;
      settings.contact.time_step = spec.dt;  // the scene's step, as the scene sets it
      try {
        const tools::Probe probe(settings, Vec3::Zero());
      } catch (const std::invalid_argument& e) {
        require(false, field(k, "probe") + ": " + e.what());
      }
    }
  }
}

}  // namespace incise::sim::surgery
