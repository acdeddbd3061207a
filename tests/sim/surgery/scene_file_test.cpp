// Surgical scene files (sim/surgery/scene_file.h): the shipped scene files are the presets with
// their tools (the same spec, node for node, toughness per label), left-out members take the
// preset's values, and every bad input names its JSON path.

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <typeinfo>
#include <vector>

#include <gtest/gtest.h>

#include "sim/surgery/scene_file.h"

namespace incise::sim::surgery {
namespace {

using nlohmann::json;

json read_json(const std::string& file) {
  std::ifstream stream(file);
  std::ostringstream text;
  text << stream.rdbuf();
  return json::parse(text.str());
}

void expect_same_tool(const ToolSpec& a, const ToolSpec& b, std::size_t k) {
  SCOPED_TRACE("tool " + std::to_string(k));
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(a.device, b.device);
  EXPECT_EQ(a.shaft_length, b.shaft_length);
  EXPECT_EQ(a.shaft_radius, b.shaft_radius);
  EXPECT_EQ(a.probe.radius, b.probe.radius);
  EXPECT_EQ(a.probe.coupling_stiffness, b.probe.coupling_stiffness);
  EXPECT_EQ(a.probe.allowed_penetration, b.probe.allowed_penetration);
  EXPECT_EQ(a.probe.max_force, b.probe.max_force);
  EXPECT_EQ(a.grasp.jaw_length, b.grasp.jaw_length);
  EXPECT_EQ(a.grasp.jaw_radius, b.grasp.jaw_radius);
  EXPECT_EQ(a.grasp.tear_force, b.grasp.tear_force);
  EXPECT_EQ(a.max_jaw_angle, b.max_jaw_angle);
  EXPECT_EQ(a.blade_length, b.blade_length);
  EXPECT_EQ(a.view_angle_degrees, b.view_angle_degrees);
  EXPECT_EQ(a.field_of_view_degrees, b.field_of_view_degrees);
}

void expect_same_tools(const std::vector<ToolSpec>& a, const std::vector<ToolSpec>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k)
    expect_same_tool(a[k], b[k], k);
}

void expect_same_material(const Material& a, const Material& b) {
  EXPECT_EQ(a.model, b.model);
  EXPECT_EQ(a.youngs_modulus, b.youngs_modulus);
  EXPECT_EQ(a.poisson_ratio, b.poisson_ratio);
  EXPECT_EQ(a.density, b.density);
  EXPECT_EQ(a.damping, b.damping);
}

// The whole spec: mesh, held nodes, step, tools, damage settings; the model through what it
// makes of the mesh (its kind and its lumped masses, which carry the densities).
void expect_same_setup(const SurgicalSceneSetup& a, const SurgicalSceneSetup& b) {
  EXPECT_EQ(a.name, b.name);
  const SurgicalSceneSpec& s = a.spec;
  const SurgicalSceneSpec& t = b.spec;
  EXPECT_EQ(s.tissue.rest, t.tissue.rest);
  EXPECT_EQ(s.tissue.tets, t.tissue.tets);
  EXPECT_EQ(s.tissue.labels, t.tissue.labels);
  EXPECT_EQ(s.fixed, t.fixed);
  EXPECT_EQ(s.dt, t.dt);
  EXPECT_EQ(s.wave_speed, t.wave_speed);
  EXPECT_EQ(s.damping_time, t.damping_time);
  EXPECT_EQ(s.ambient_damping, t.ambient_damping);
  EXPECT_EQ(s.adaptivity.enabled, t.adaptivity.enabled);
  EXPECT_EQ(s.adaptivity.edge_length, t.adaptivity.edge_length);
  EXPECT_EQ(s.adaptivity.radius, t.adaptivity.radius);
  EXPECT_EQ(s.adaptivity.coarsen_after, t.adaptivity.coarsen_after);
  EXPECT_EQ(s.adaptivity.max_splits, t.adaptivity.max_splits);
  EXPECT_EQ(s.far_field.enabled, t.far_field.enabled);
  EXPECT_EQ(s.far_field.centre, t.far_field.centre);
  EXPECT_EQ(s.far_field.radius, t.far_field.radius);
  ASSERT_EQ(s.far_field.materials.size(), t.far_field.materials.size());
  for (std::size_t k = 0; k < s.far_field.materials.size(); ++k) {
    EXPECT_EQ(s.far_field.materials[k].youngs_modulus, t.far_field.materials[k].youngs_modulus);
    EXPECT_EQ(s.far_field.materials[k].damping, t.far_field.materials[k].damping);
  }
  EXPECT_EQ(s.cut_every, t.cut_every);
  EXPECT_EQ(s.damage_every, t.damage_every);
  ASSERT_EQ(s.bones.size(), t.bones.size());
  for (std::size_t b_ = 0; b_ < s.bones.size(); ++b_) {
    EXPECT_EQ(s.bones[b_].vertices, t.bones[b_].vertices);
    EXPECT_EQ(s.bones[b_].triangles, t.bones[b_].triangles);
  }
  expect_same_tools(s.tools, t.tools);
  ASSERT_EQ(s.damage.strain_thresholds.size(), t.damage.strain_thresholds.size());
  for (std::size_t k = 0; k < s.damage.strain_thresholds.size(); ++k) {
    EXPECT_EQ(s.damage.strain_thresholds[k].label, t.damage.strain_thresholds[k].label);
    EXPECT_EQ(s.damage.strain_thresholds[k].max_principal_strain,
              t.damage.strain_thresholds[k].max_principal_strain);
  }
  EXPECT_EQ(s.damage.protected_labels, t.damage.protected_labels);
  ASSERT_EQ(s.toughness.size(), t.toughness.size());
  for (std::size_t k = 0; k < s.toughness.size(); ++k) {
    EXPECT_EQ(s.toughness[k].label, t.toughness[k].label);
    EXPECT_EQ(s.toughness[k].toughness, t.toughness[k].toughness);
  }
  EXPECT_EQ(s.default_toughness, t.default_toughness);
  EXPECT_EQ(s.cutting.ramp_speed, t.cutting.ramp_speed);
  EXPECT_EQ(s.cutting.max_force, t.cutting.max_force);
  EXPECT_EQ(s.damage.target.line, t.damage.target.line);
  EXPECT_EQ(s.damage.target.half_width, t.damage.target.half_width);
  const auto model_a = s.model(s.tissue);
  const auto model_b = t.model(t.tissue);
  EXPECT_EQ(typeid(*model_a), typeid(*model_b));
  EXPECT_EQ(model_a->masses(), model_b->masses());
  EXPECT_EQ(a.cut_target, b.cut_target);
  EXPECT_EQ(a.landmarks.size(), b.landmarks.size());
  EXPECT_EQ(a.portals.size(), b.portals.size());
}

TEST(SceneFile, TheShippedLiverFileIsThePresetWithAProbeAGrasperAndAScalpel) {
  const SurgicalSceneFile file =
      parse_surgical_scene_file(read_json(INCISE_SCENES_DIR "/surgery/liver_surgery.json"));
  LiverSceneOptions expected;
  ToolSpec scalpel = make_tool(ToolKind::scalpel, 2);
  scalpel.blade_length = 0.012;
  expected.tools = {make_tool(ToolKind::probe, 0), make_tool(ToolKind::grasper, 1), scalpel};
  ASSERT_EQ(file.anatomy, Anatomy::liver);
  expect_same_tools(file.liver.tools, expected.tools);
  expect_same_material(file.liver.liver, expected.liver);
  EXPECT_EQ(file.liver.liver_toughness, expected.liver_toughness);
  EXPECT_EQ(file.liver.anatomy.cell_size, expected.anatomy.cell_size);
  EXPECT_EQ(file.liver.anatomy.length, expected.anatomy.length);
  EXPECT_EQ(file.liver.strain_threshold, expected.strain_threshold);
  EXPECT_EQ(file.liver.target_half_width, expected.target_half_width);
  expect_same_setup(build_surgical_scene(file), make_liver_surgery(expected));
}

TEST(SceneFile, TheShippedKneeFileIsThePresetWithAScopeAProbeAndAScalpel) {
  const SurgicalSceneFile file =
      parse_surgical_scene_file(read_json(INCISE_SCENES_DIR "/surgery/knee_surgery.json"));
  KneeSceneOptions expected;
  ToolSpec scalpel = make_tool(ToolKind::scalpel, 2);
  scalpel.blade_length = 0.02;
  expected.tools = KneeSceneOptions::default_tools();
  expected.tools.push_back(scalpel);
  ASSERT_EQ(file.anatomy, Anatomy::knee);
  expect_same_tools(file.knee.tools, expected.tools);
  expect_same_material(file.knee.meniscus, expected.meniscus);
  expect_same_material(file.knee.ligament, expected.ligament);
  EXPECT_EQ(file.knee.meniscus_toughness, expected.meniscus_toughness);
  EXPECT_EQ(file.knee.ligament_toughness, expected.ligament_toughness);
  EXPECT_EQ(file.knee.anatomy.tissue_cell_size, expected.anatomy.tissue_cell_size);
  EXPECT_EQ(file.knee.strain_threshold, expected.strain_threshold);
  expect_same_setup(build_surgical_scene(file), make_knee_surgery(expected));
}

// Left-out members are the preset's; a listed tool starts from the preset's tool of its kind.
TEST(SceneFile, DefaultsAreThePresets) {
  const SurgicalSceneFile liver = parse_surgical_scene_file(json{{"anatomy", "liver"}});
  const LiverSceneOptions preset;
  expect_same_tools(liver.liver.tools, preset.tools);
  expect_same_material(liver.liver.liver, preset.liver);
  EXPECT_EQ(liver.liver.liver_toughness, preset.liver_toughness);
  EXPECT_EQ(preset.liver_toughness, 200);  // docs/surgical_scene_files.md
  EXPECT_EQ(liver.liver.anatomy.cell_size, preset.anatomy.cell_size);
  EXPECT_EQ(liver.liver.anatomy.cut_points, preset.anatomy.cut_points);
  EXPECT_EQ(liver.cut_every, SurgicalSceneSpec{}.cut_every);
  EXPECT_EQ(liver.damage_every, SurgicalSceneSpec{}.damage_every);

  const SurgicalSceneFile knee = parse_surgical_scene_file(json::parse(R"({
    "anatomy": "knee", "anatomy_options": {"flexion_deg": 30},
    "materials": {"ligament": {"E": 80000}, "meniscus": {"toughness": 750}},
    "tools": [{"kind": "probe", "device": 1},
              {"kind": "grasper", "device": 0, "tear_force": 2, "reach": 0.007}],
    "ambient_damping": 0, "solver": {"cut_every": 5},
    "adaptivity": {"enabled": true, "radius": 0.02}})"));
  const KneeSceneOptions knee_preset;
  EXPECT_EQ(knee.knee.anatomy.flexion_deg, 30);
  EXPECT_EQ(knee.knee.anatomy.voxel_size, knee_preset.anatomy.voxel_size);
  EXPECT_EQ(knee.knee.ligament.youngs_modulus, 80000);
  EXPECT_EQ(knee.knee.ligament.density, knee_preset.ligament.density);
  expect_same_material(knee.knee.meniscus, knee_preset.meniscus);
  // Toughness on its own over the preset's, per tissue, and into the spec per label.
  EXPECT_EQ(knee.knee.meniscus_toughness, 750);
  EXPECT_EQ(knee.knee.ligament_toughness, knee_preset.ligament_toughness);
  const SurgicalSceneSpec knee_spec = build_surgical_scene(knee).spec;
  ASSERT_EQ(knee_spec.toughness.size(), 3u);  // the two menisci and the ligament
  int at_750 = 0;
  for (const LabelToughness& t : knee_spec.toughness) {
    if (t.toughness == 750) {
      ++at_750;
    } else {
      EXPECT_EQ(t.toughness, knee_preset.ligament_toughness) << "label " << t.label;
    }
  }
  EXPECT_EQ(at_750, 2);
  ASSERT_EQ(knee.knee.tools.size(), 2u);
  expect_same_tool(knee.knee.tools[0], knee_preset.tools[1], 0);  // the hook probe
  ToolSpec grasper = make_tool(ToolKind::grasper, 0);
  grasper.grasp.tear_force = 2;
  grasper.grasp.reach = 0.007;
  expect_same_tool(knee.knee.tools[1], grasper, 1);
  EXPECT_EQ(knee.cut_every, 5);
  EXPECT_EQ(knee.knee.ambient_damping, 0);
  EXPECT_EQ(build_surgical_scene(knee).spec.ambient_damping, 0);
  EXPECT_EQ(liver.liver.ambient_damping, preset.ambient_damping);
  EXPECT_GT(preset.ambient_damping, 0);
  // Adaptivity: each member on its own over the preset's.
  EXPECT_TRUE(build_surgical_scene(knee).spec.adaptivity.enabled);  // the preset: off
  EXPECT_FALSE(knee_preset.adaptivity.enabled);
  EXPECT_EQ(knee.knee.adaptivity.radius, 0.02);
  EXPECT_EQ(knee.knee.adaptivity.edge_length, knee_preset.adaptivity.edge_length);
  EXPECT_TRUE(build_surgical_scene(liver).spec.adaptivity.enabled);
  EXPECT_FALSE(build_surgical_scene(liver).spec.far_field.enabled);  // the preset: none
  const SurgicalSceneSetup condensed = build_surgical_scene(
      parse_surgical_scene_file(json{{"anatomy", "liver"}, {"operational_radius", 0.05}}));
  EXPECT_TRUE(condensed.spec.far_field.enabled);
  EXPECT_EQ(condensed.spec.far_field.radius, 0.05);
  EXPECT_EQ(condensed.spec.far_field.centre,
            0.5 * (condensed.cut_target.front() + condensed.cut_target.back()));
}

struct BadCase {
  const char* json;
  const char* error;  // SceneError::what(): "<path>: <reason>"
};

TEST(SceneFile, EveryBadInputNamesItsPath) {
  const BadCase cases[] = {
      {R"([])", "the scene must be a JSON object (got [])"},
      {R"({})", "anatomy: is required"},
      {R"({"anatomy": "spleen"})", R"(anatomy: "spleen" is not one of liver, knee)"},
      {R"({"anatomy": "liver", "tool": []})",
       "tool: unknown key (expected one of: description, anatomy, anatomy_options, materials, "
       "ambient_damping, adaptivity, operational_radius, tools, damage, solver)"},
      {R"({"anatomy": "liver", "operational_radius": -0.01})",
       "operational_radius: must be >= 0 (got -0.01)"},
      {R"({"anatomy": "knee", "operational_radius": 0.03})",
       "operational_radius: is a setting of the liver, not of the knee"},
      {R"({"anatomy": "liver", "adaptivity": {"enabled": 1}})",
       "adaptivity.enabled: must be true or false (got 1)"},
      {R"({"anatomy": "liver", "adaptivity": {"edge_length": 0}})",
       "adaptivity.edge_length: must be > 0 (got 0)"},
      {R"({"anatomy": "knee", "adaptivity": {"max_splits": 0}})",
       "adaptivity.max_splits: must be in [1, 2147483647] (got 0)"},
      {R"({"anatomy": "knee", "adaptivity": {"radius": 0.01, "size": 2}})",
       "adaptivity.size: unknown key (expected one of: enabled, edge_length, radius, "
       "coarsen_after, "
       "max_splits)"},
      {R"({"anatomy": "liver", "ambient_damping": -1})", "ambient_damping: must be >= 0 (got -1)"},
      {R"({"anatomy": "knee", "ambient_damping": "20"})",
       R"(ambient_damping: must be a number (got "20"))"},
      {R"({"anatomy": "liver", "tools": {}})", "tools: must be an array (got {})"},
      {R"({"anatomy": "liver", "tools": [{"kind": "probe", "device": 0}, {"kind": "saw"}]})",
       R"(tools[1].kind: "saw" is not one of probe, grasper, scalpel, scope)"},
      {R"({"anatomy": "liver", "tools": [{"kind": "probe"}]})", "tools[0].device: is required"},
      {R"({"anatomy": "liver", "tools": [{"kind": "probe", "device": -1}]})",
       "tools[0].device: must be in [0, 15] (got -1)"},
      {R"({"anatomy": "liver", "tools": [{"kind": "probe", "device": 0, "jaw_length": 0.01}]})",
       "tools[0].jaw_length: is a setting of grasper, not of a probe"},
      {R"({"anatomy": "knee", "tools": [{"kind": "scope", "device": 0, "radius": 0.01}]})",
       "tools[0].radius: is a setting of probe, not of a scope"},
      {R"({"anatomy": "liver", "tools": [{"kind": "probe", "device": 0, "radius": 0.0001}]})",
       "tools[0].radius: must be > 5e-04 (got 1e-04)"},
      {R"({"anatomy": "liver", "tools": [{"kind": "scalpel", "device": 2, "blade_length": 0}]})",
       "tools[0].blade_length: must be > 0 (got 0)"},
      {R"({"anatomy": "knee", "tools": [{"kind": "scope", "device": 0,
           "view_angle_degrees": 90}]})",
       "tools[0].view_angle_degrees: must be in [0, 90) (got 90)"},
      {R"({"anatomy": "liver", "tools": [{"kind": "grasper", "device": 0, "max_jaw_angle": 4}]})",
       "tools[0].max_jaw_angle: must be in (0, 3.141592653589793) (got 4)"},
      {R"({"anatomy": "liver", "tools": [{"kind": "probe", "device": 0, "shaft": 1}]})",
       "tools[0].shaft: unknown key (expected one of: kind, device, shaft_length, shaft_radius, "
       "radius, coupling_stiffness, max_force, tear_force, jaw_length, reach, max_jaw_angle, "
       "blade_length, view_angle_degrees, field_of_view_degrees)"},
      {R"({"anatomy": "liver", "tools": [{"kind": "grasper", "device": 0, "reach": -0.001}]})",
       "tools[0].reach: must be >= 0 (got -0.001)"},
      {R"({"anatomy": "liver", "tools": [{"kind": "scalpel", "device": 0, "reach": 0.005}]})",
       "tools[0].reach: is a setting of grasper, not of a scalpel"},
      {R"({"anatomy": "liver", "materials": {"liver": {"nu": 0.5}}})",
       "materials.liver.nu: must be in (-1, 0.5) (got 0.5)"},
      {R"({"anatomy": "liver", "materials": {"liver": {"E": "4"}}})",
       R"(materials.liver.E: must be a number (got "4"))"},
      {R"({"anatomy": "liver", "materials": {"liver": {"toughness": -1}}})",
       "materials.liver.toughness: must be >= 0 (got -1)"},
      {R"({"anatomy": "knee", "materials": {"ligament": {"toughness": "hard"}}})",
       R"(materials.ligament.toughness: must be a number (got "hard"))"},
      {R"({"anatomy": "knee", "materials": {"meniscus": {"tough": 500}}})",
       "materials.meniscus.tough: unknown key (expected one of: model, E, nu, density, damping, "
       "toughness)"},
      {R"({"anatomy": "liver", "materials": {"meniscus": {}}})",
       "materials.meniscus: unknown key (expected one of: liver)"},
      {R"({"anatomy": "knee", "materials": {"ligament": {"model": "foam"}}})",
       R"(materials.ligament.model: "foam" is not one of mss, linear, corotational, )"
       R"(corotational_polar, corotational_nodal_pressure, stvk, neohookean)"},
      {R"({"anatomy": "liver", "anatomy_options": {"cell_size": 0.1}})",
       "anatomy_options.cell_size: cell_size [m] = 0.1 is outside [0.00266667, 0.032]"},
      {R"({"anatomy": "knee", "anatomy_options": {"flexion_deg": 100}})",
       "anatomy_options.flexion_deg: flexion_deg = 100 is outside [0, 90]"},
      {R"({"anatomy": "knee", "anatomy_options": {"cell_size": 0.002}})",
       "anatomy_options.cell_size: unknown key (expected one of: voxel_size, tissue_cell_size, "
       "bone_facet_size, flexion_deg)"},
      {R"({"anatomy": "liver", "damage": {"strain_threshold": -1}})",
       "damage.strain_threshold: must be > 0 (got -1)"},
      {R"({"anatomy": "liver", "solver": {"cut_every": 0}})",
       "solver.cut_every: must be in [1, 2147483647] (got 0)"},
      {R"({"anatomy": "liver", "solver": {"damage_every": 1.5}})",
       "solver.damage_every: must be an integer (got 1.5)"},
      {R"({"anatomy": "knee", "solver": {"time_step": -1}})",
       "solver.time_step: must be in [0, 0.01] (got -1)"},
      {R"({"anatomy": "liver", "solver": {"time_step": 0.02}})",
       "solver.time_step: must be in [0, 0.01] (got 0.02)"},
      {R"({"anatomy": "liver", "solver": {"step": 0.001}})",
       "solver.step: unknown key (expected one of: cut_every, damage_every, time_step)"},
  };
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.json);
    try {
      parse_surgical_scene_file(json::parse(c.json));
      ADD_FAILURE() << "accepted";
    } catch (const SceneError& error) {
      EXPECT_EQ(std::string(error.what()), c.error);
    }
  }
  // A toughness that is not finite (JSON has no literal for it; a reader's value may still be).
  for (const Real bad :
       {std::numeric_limits<Real>::infinity(), -std::numeric_limits<Real>::infinity(),
        std::numeric_limits<Real>::quiet_NaN()}) {
    json scene = {{"anatomy", "liver"}, {"materials", {{"liver", {{"toughness", bad}}}}}};
    try {
      parse_surgical_scene_file(scene);
      ADD_FAILURE() << "accepted " << bad;
    } catch (const SceneError& error) {
      EXPECT_EQ(error.path(), "materials.liver.toughness") << error.what();
    }
  }
  // Malformed text fails before anything is meshed.
  try {
    parse_surgical_scene("{\"anatomy\": ");
    ADD_FAILURE() << "accepted";
  } catch (const SceneError& error) {
    EXPECT_EQ(error.path(), "");
    EXPECT_EQ(std::string(error.what()).rfind("malformed JSON: ", 0), 0u) << error.what();
  }
}

}  // namespace
}  // namespace incise::sim::surgery
