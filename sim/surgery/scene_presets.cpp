#include "sim/surgery/scene_presets.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim/mesh/box_mesher.h"
#include "sim/scene/node_selection.h"
#include "sim/scene/scene_error.h"
#include "sim/scene/scene_run.h"
#include "sim/scene/scene_validation.h"
#include "sim/solve/stable_time_step.h"

namespace incise::sim::surgery {

namespace {

// The model of a scene whose tissue labels carry the given materials (every label listed; the
// model kind is the first one's: a scene has one model).
Scene scene_of(const std::map<int, Material>& materials) {
  Scene scene;
  scene.material = materials.begin()->second;
  scene.materials_by_label = materials;
  return scene;
}

ModelFactory model_of(const std::map<int, Material>& materials) {
  return [scene = scene_of(materials)](const TetMesh& mesh) { return make_model(scene, mesh); };
}

// The sliver guard's wave speed and damping time of a tissue mesh with these materials: the
// fastest material's P-wave speed c, and beta = damping l_min / c (scene_run.h's Kelvin-Voigt
// time; for the mass-spring model, a bound of the same order). Returns l_min / c, the time a wave
// takes across the smallest altitude.
Real set_guard(SurgicalSceneSpec& spec, const std::map<int, Material>& materials) {
  Real c = 0, damping = 0;
  for (const auto& [label, m] : materials) {
    c = std::max(c, p_wave_speed(m.youngs_modulus, m.poisson_ratio, m.density));
    damping = std::max(damping, m.damping);
  }
  const Real l_min = element_lengths(spec.tissue.rest, spec.tissue.tets).min_altitude;
  spec.wave_speed = c;
  spec.damping_time = damping * l_min / c;
  return l_min / c;
}

// set_guard, and dt the stable step of the fastest material on the smallest altitude.
void set_step(SurgicalSceneSpec& spec, const std::map<int, Material>& materials) {
  spec.dt = kExplicitSafety * set_guard(spec, materials);
}

// Mass scaling (SurgicalSceneSetup::mass_scale): scales the materials' densities so that the
// stable step is time_step, if that is longer; returns the scale (1: unchanged).
Real scale_masses(SurgicalSceneSpec& spec, std::map<int, Material>& materials, Real time_step) {
  set_step(spec, materials);
  if (!(time_step > spec.dt)) return 1;
  const Real scale = (time_step / spec.dt) * (time_step / spec.dt);
  for (auto& [label, m] : materials) {
    (void)label;
    m.density *= scale;
  }
  return scale;
}

void check_time_step(Real time_step) {
  if (!(std::isfinite(time_step) && time_step >= 0 && time_step <= 0.01)) {
    throw std::invalid_argument("time_step must be in [0, 0.01] s, got " +
                                std::to_string(time_step));
  }
}

tools::MarkedTarget target_of(const std::vector<Vec3>& line, Real half_width) {
  tools::MarkedTarget target;
  target.line.resize(static_cast<Eigen::Index>(line.size()), 3);
  for (std::size_t k = 0; k < line.size(); ++k)
    target.line.row(static_cast<Eigen::Index>(k)) = line[k].transpose();
  target.depth_direction = -Vec3::UnitZ();
  target.depth = 0.01;  // a cut may go 1 cm deep under the marked line
  target.half_width = half_width;
  return target;
}

std::vector<char> held(int nodes, const std::vector<int>& held_nodes) {
  std::vector<char> fixed(static_cast<std::size_t>(nodes), 0);
  for (const int i : held_nodes)
    fixed[static_cast<std::size_t>(i)] = 1;
  return fixed;
}

}  // namespace

std::vector<ToolSpec> LiverSceneOptions::default_tools() {
  return {make_tool(ToolKind::probe, 0), make_tool(ToolKind::grasper, 1)};
}

std::vector<ToolSpec> KneeSceneOptions::default_tools() {
  ToolSpec scope = make_tool(ToolKind::scope, 0);
  scope.shaft_radius = 0.002;  // a 4 mm arthroscope
  ToolSpec probe = make_tool(ToolKind::probe, 1);
  probe.probe.radius = 0.0015;  // a hook probe's tip
  probe.shaft_radius = 0.0015;
  return {scope, probe};
}

SurgicalSceneSetup make_block_surgery(const Scene& block, const BlockSceneOptions& options) {
  validate_scene(block);
  if (options.hands < 1 || options.hands > 2) {
    throw std::invalid_argument("a block has probes for 1 or 2 hands");
  }
  if (block.mesh.source != MeshSource::box) {
    throw SceneError("mesh", "a live block is a box (\"mesh\": {\"box\": ...})");
  }
  if (!block.loads.empty()) throw SceneError("loads", "a live block takes no loads");
  if (block.adaptivity) throw SceneError("adaptivity", "a live block does not remesh");
  if (block.solver.integrator != Integrator::symplectic_euler) {
    throw SceneError("solver.integrator", "a live block steps with \"symplectic_euler\"");
  }
  SurgicalSceneSetup setup;
  setup.name = "block";
  setup.tissue_names = {{0, "tissue"}};
  setup.view = block.view;
  setup.tools_stand_for_any = true;
  SurgicalSceneSpec& spec = setup.spec;
  spec.tissue = make_box_mesh(block.mesh.box.size, block.mesh.box.cells);
  const TetMesh& mesh = spec.tissue;
  spec.fixed = held_at_rest(block, mesh);
  spec.model = [scene = block](const TetMesh& m) { return make_model(scene, m); };
  spec.dt = block.solver.dt;
  // Every material a label may take (a label without its own takes "material").
  std::map<int, Material> materials = block.materials_by_label;
  materials.emplace(-1, block.material);
  set_guard(spec, materials);
  spec.gravity = block.gravity;
  const SphereTool sphere = block.tool.value_or(SphereTool{});
  for (int hand = 0; hand < options.hands; ++hand) {
    ToolSpec probe = make_tool(ToolKind::probe, hand);
    probe.probe.radius = sphere.radius;
    probe.probe.coupling_stiffness = sphere.stiffness;
    probe.probe.max_force = options.max_force;
    probe.upright = true;  // drawn standing, whatever the device's orientation
    spec.tools.push_back(probe);
  }
  std::vector<int> labels(mesh.labels.data(), mesh.labels.data() + mesh.labels.size());
  if (labels.empty()) labels.push_back(0);
  std::sort(labels.begin(), labels.end());
  labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
  for (const int label : labels)
    spec.damage.strain_thresholds.push_back({label, options.strain_threshold});
  spec.damage_every =
      std::max(1, static_cast<int>(std::lround(options.damage_interval_s / spec.dt)));
  return setup;
}

SurgicalSceneSetup make_liver_surgery(const LiverSceneOptions& options) {
  LiverAnatomy liver = make_liver_scene(options.anatomy);
  SurgicalSceneSetup setup;
  setup.name = "liver";
  setup.tissue_names = {{kLiverLabel, "liver"}, {kGallbladderBedLabel, "gallbladder bed"}};
  SurgicalSceneSpec& spec = setup.spec;
  std::map<int, Material> materials = {{kLiverLabel, options.liver},
                                       {kGallbladderBedLabel, options.liver}};
  check_time_step(options.time_step);
  spec.fixed = held(liver.organ.num_nodes(), liver.held_nodes);
  spec.tissue = std::move(liver.organ);
  setup.mass_scale = scale_masses(spec, materials, options.time_step);
  spec.model = model_of(materials);
  set_step(spec, materials);
  spec.ambient_damping = options.ambient_damping;
  spec.adaptivity = options.adaptivity;
  spec.tools = options.tools;
  spec.toughness = {{kLiverLabel, options.liver_toughness},
                    {kGallbladderBedLabel, options.liver_toughness}};
  spec.damage.strain_thresholds = {{kLiverLabel, options.strain_threshold},
                                   {kGallbladderBedLabel, options.strain_threshold}};
  spec.damage.protected_labels = liver.protected_labels;
  spec.damage.target = target_of(liver.cut_line, options.target_half_width);
  if (options.operational_radius > 0) {
    spec.far_field.enabled = true;
    spec.far_field.centre = 0.5 * (liver.cut_line.front() + liver.cut_line.back());
    spec.far_field.radius = options.operational_radius;
    spec.far_field.materials = element_materials(scene_of(materials), spec.tissue);
  }
  setup.surroundings = liver_surroundings(Box3(spec.tissue.rest.colwise().minCoeff().transpose(),
                                               spec.tissue.rest.colwise().maxCoeff().transpose()),
                                          liver.shape.flat_side_z);
  setup.landmarks = std::move(liver.landmarks);
  setup.cut_target = std::move(liver.cut_line);
  return setup;
}

SurgicalSceneSetup make_knee_surgery(const KneeSceneOptions& options) {
  KneeAnatomy knee = make_knee(options.anatomy);
  SurgicalSceneSetup setup;
  setup.name = "knee";
  setup.tissue_names = {{kMedialMeniscusLabel, "meniscus"},
                        {kLateralMeniscusLabel, "meniscus"},
                        {kLigamentLabel, "ligament"}};
  SurgicalSceneSpec& spec = setup.spec;
  std::map<int, Material> materials = {{kMedialMeniscusLabel, options.meniscus},
                                       {kLateralMeniscusLabel, options.meniscus},
                                       {kLigamentLabel, options.ligament}};
  check_time_step(options.time_step);
  spec.fixed = held(knee.tissue.num_nodes(), knee.held_nodes);
  spec.tissue = std::move(knee.tissue);
  setup.mass_scale = scale_masses(spec, materials, options.time_step);
  spec.model = model_of(materials);
  set_step(spec, materials);
  spec.ambient_damping = options.ambient_damping;
  spec.adaptivity = options.adaptivity;
  spec.tools = options.tools;
  spec.toughness = {{kMedialMeniscusLabel, options.meniscus_toughness},
                    {kLateralMeniscusLabel, options.meniscus_toughness},
                    {kLigamentLabel, options.ligament_toughness}};
  spec.bones = {{"femur", knee.femur.vertices, knee.femur.triangles},
                {"tibia", knee.tibia.vertices, knee.tibia.triangles}};
  for (const auto& [label, m] : materials) {
    (void)m;
    spec.damage.strain_thresholds.push_back({label, options.strain_threshold});
  }
  spec.damage.protected_labels = knee.protected_labels;
  spec.damage.target = target_of(knee.cut_target, options.target_half_width);
  std::vector<Surrounding> bones;
  for (const BoneSpec& bone : spec.bones)
    bones.push_back({bone.name, SurroundingKind::bone, bone.vertices, bone.triangles});
  setup.surroundings =
      knee_surroundings(std::move(bones), Box3(spec.tissue.rest.colwise().minCoeff().transpose(),
                                               spec.tissue.rest.colwise().maxCoeff().transpose()));
  setup.landmarks = std::move(knee.landmarks);
  setup.portals = std::move(knee.portals);
  setup.cut_target = std::move(knee.cut_target);
  return setup;
}

}  // namespace incise::sim::surgery
