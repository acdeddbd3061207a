#pragma once

// The surgical scenes, built from the generated anatomy (sim/mesh/cgal/
// anatomy.h) into a SurgicalSceneSpec with their tools:
//   liver  a liver-like organ held on its flat side, for laparoscopic probing, grasping and
//          cutting along a marked line (the cut target); the gallbladder bed is protected;
//   block  a sim core scene (sim/scenes/*.json: a box of tissue on its fixed face, the palpation
//          block) with a probe in each hand: the live sessions run every scene on this one
//          runtime;
//   knee   a knee-like joint: rigid femur and tibia (FCL surfaces), deformable menisci and ACL
//          from a labelled volume, held at their attachments; a 30-degree arthroscope and a
//          probe, for inspection (landmarks) and a meniscus cut (the medial meniscus's radial
//          tear line); the ACL is protected (cutting it is a never event).
// Each models only what it needs: the bones are rigid surfaces, only the soft tissue is
// simulated. The time step is the tissue's stable step (stable_time_step, kExplicitSafety); the
// wave speed and damping time for TissueBody's sliver guard follow the materials.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "sim/mesh/cgal/anatomy.h"
#include "sim/scene/scene.h"
#include "sim/surgery/surgical_scene.h"
#include "sim/surgery/surroundings.h"

namespace incise::sim::surgery {

// A scene ready to run, with what a task and the renderer need to know about it.
struct SurgicalSceneSetup {
  std::string name;  // "liver" or "knee"
  SurgicalSceneSpec spec;
  std::vector<Landmark> landmarks;
  std::vector<Portal> portals;   // knee: where the scope and the probe enter
  std::vector<Vec3> cut_target;  // the marked line [m]
  std::optional<ViewSpec> view;  // the scene's own camera, if it names one (the block's "view")
  // The block's probes stand for any tool a task names (a "retractor" is a probe that holds).
  bool tools_stand_for_any = false;
  // Mass scaling: a time_step longer than the tissue's stable step is made stable by scaling every
  // tissue density by mass_scale = (time_step / stable step)^2 (the P-wave speed falls by its
  // square root). Static deformation and forces are unchanged (no gravity in these scenes);
  // motion is slower: every vibration mode's frequency falls by sqrt(mass_scale), the tissue's
  // Kelvin-Voigt time (damping l_min / c) grows by it, inertial forces by mass_scale, and the
  // ambient damping's time constant stays. 1: none.
  Real mass_scale = 1;
  // What frames the tissue in the picture (the knee's bones and capsule, the liver's neighbours
  // and the abdominal wall); none for the block.
  std::vector<Surrounding> surroundings;
  // What each tissue label of the mesh is, for the picture's looks: "liver", "gallbladder bed",
  // "meniscus", "ligament"; the block's label 0 "tissue".
  std::map<int, std::string> tissue_names;
};

struct LiverSceneOptions {
  LiverOptions anatomy;
  // Liver parenchyma (soft, near-incompressible in life; nu 0.45 keeps the explicit step
  // affordable) and the gallbladder bed, both corotational with polar rotations (robust to
  // inversion under a hard push).
  Material liver{MaterialModel::corotational_polar, 4000, 0.45, 1050, 0.3, 0};
  // Its toughness, the work to cut a unit area [J/m^2] (the scalpel's resistance; the order of
  // magnitude measured on animal liver, tools/cutting_resistance.h).
  Real liver_toughness = tools::kDefaultToughness;
  Real strain_threshold = 0.4;     // max principal Green strain that damages the liver [-]
  Real target_half_width = 0.003;  // a cut within this of the marked line is on target [m]
  // What surrounds the tissue, as mass-proportional damping [1/s] (SurgicalSceneSpec): a time
  // constant of 50 ms, about critical for the organ's lowest mode.
  Real ambient_damping = 20;
  // Refinement around the probe's contact and the grasper's jaws: the 8 mm cells down to 4 mm
  // edges within 12 mm (SurgicalSceneSpec::adaptivity).
  AdaptivitySpec adaptivity{true, 0.004, 0.012, 0.1, 2000};
  // Where the surgery happens: a ball of this radius [m] around the marked line's middle; the
  // rest of the organ is a condensed linear far field (SurgicalSceneSpec::far_field). 0: none,
  // the whole organ nonlinear (the default: on this thin organ most far-field nodes are surface
  // nodes, which the condensed model keeps, and its dense K* costs about what the nonlinear
  // elements it replaces do; docs/surgical_scenes.md has the figures).
  Real operational_radius = 0;
  // The step [s]; 0 or anything up to the tissue's stable step: the stable step (see mass_scale).
  Real time_step = 0;
  std::vector<ToolSpec> tools = default_tools();
  static std::vector<ToolSpec> default_tools();  // a probe on device 0, a grasper on device 1
};

struct KneeSceneOptions {
  KneeOptions anatomy{0.001, 0.003, 0.005, 10};
  // Menisci and ligament, kept soft enough for an explicit step (real menisci are far stiffer:
  // the scene trades stiffness for rate, and the bones carry the joint).
  Material meniscus{MaterialModel::corotational_polar, 30000, 0.3, 1100, 0.3, 0};
  Material ligament{MaterialModel::corotational_polar, 60000, 0.3, 1100, 0.3, 0};
  // Toughness [J/m^2]: fibrocartilage and ligament are tougher than liver (cartilage measures in
  // the hundreds to a thousand); rough orders of magnitude, docs/cutting.md.
  Real meniscus_toughness = 500;
  Real ligament_toughness = 1000;
  Real strain_threshold = 0.25;
  Real target_half_width = 0.0015;
  // What surrounds the tissue (the joint capsule and fluid, the bones the menisci sit between), as
  // mass-proportional damping [1/s]: a time constant of 10 ms (the menisci's lowest modes are near
  // 65 Hz; at 20/s a jerked meniscus was still tangled after the suite's 60 ms settle).
  Real ambient_damping = 100;
  // No refinement by default: a split of the 3 mm cells would need a shorter step than the
  // tissue's (43 us at 3 mm cells; bench_surgery's probe landing, on the older mesh, made 6 splits
  // and refused 718, at 4.9 ms).
  AdaptivitySpec adaptivity{false, 0.0015, 0.005, 0.1, 2000};
  // The step [s]; 0 or anything up to the tissue's stable step: the stable step (see mass_scale).
  Real time_step = 0;
  std::vector<ToolSpec> tools = default_tools();
  static std::vector<ToolSpec> default_tools();  // a scope on device 0, a probe on device 1
};

// The block: a sim core scene as a surgical scene. Its tissue is the box mesh with the scene's
// material and gravity, held where a "fix" constraint holds all three axes; its step is the
// scene's solver.dt. Its "tool" (a sphere) becomes a probe on each of the devices 0 .. hands - 1:
// the sphere's radius, a virtual coupling as stiff as the sphere's penalty, saturating at
// max_force. Tissue strained beyond strain_threshold (every label) is damaged, recorded every
// damage_interval_s.
struct BlockSceneOptions {
  int hands = 2;                  // 1 or 2
  Real max_force = 20;            // [N] the probes' saturation (the session's force limit)
  Real strain_threshold = 0.4;    // [-]
  Real damage_interval_s = 0.01;  // [s]
};

// Throws SceneError naming the key for what the block cannot carry live: a mesh other than a
// box, loads, a "displace" or per-axis constraint, adaptivity, or an integrator other than
// symplectic_euler (and as validate_scene for an invalid scene).
SurgicalSceneSetup make_block_surgery(const Scene& block, const BlockSceneOptions& options = {});

// Throws std::invalid_argument for bad options (as the anatomy's checks, or a bad material).
SurgicalSceneSetup make_liver_surgery(const LiverSceneOptions& options);
SurgicalSceneSetup make_knee_surgery(const KneeSceneOptions& options);

}  // namespace incise::sim::surgery
