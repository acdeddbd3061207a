#pragma once

// A surgical scene at run time: one deformable tissue body, rigid bones, and tools
// driven by device inputs, stepped at a fixed dt. It composes the parts:
//   probe and scope tip   tools::Probe (virtual coupling, penalty contact on the surface tree);
//   grasper               tools::Grasper (grab on closing, hold, tear above its force, release);
//   scalpel               cut::ProgressiveCutter (complete cuts as the blade leaves tets, the
//                         tets it is inside split temporarily), every cut_every steps; while its
//                         stroke is open, the tissue's resistance to the cut on the tool
//                         (tools::blade_in_tissue, tools::cutting_resistance);
//   bones                 collide::RigidBody (FCL): penalty on each tool's tip and shaft, counted
//                         as collisions with protected structures;
//   damage                tools::DamageTracker (strain over thresholds, cuts against the marked
//                         target, bone contacts, never events).
// Each device gets a local force model (F0 + K) for its station agent (force_model).
//
// Tool frame: a device input gives the tool tip and an orientation R. The tool points along
// d = R e_z (from the handle to the tip); its shaft is the segment tip - s d, s in [0, length].
//   probe    the tip is the sphere's centre;
//   grasper  the tip is the jaws' hinge; the jaws open in the plane of d and R e_x, by
//            jaw * max_jaw_angle;
//   scalpel  the blade's edge runs from the tip back along the shaft for blade_length;
//   scope    the eye is at the tip; it looks along d tilted by view_angle towards -R e_y (a
//            30-degree arthroscope), with R e_y tilted alike as its up.
// Single-threaded and deterministic.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sim/collide/rigid_body.h"
#include "sim/core/clone_ptr.h"
#include "sim/core/types.h"
#include "sim/cut/progressive_cutter.h"
#include "sim/surgery/tissue_body.h"
#include "sim/tools/blade_in_tissue.h"
#include "sim/tools/cutting_resistance.h"
#include "sim/tools/damage_tracker.h"
#include "sim/tools/force_model.h"
#include "sim/tools/grasper.h"
#include "sim/tools/probe.h"

namespace incise::sim::surgery {

// One device sample in the scene frame.
struct ToolInput {
  Vec3 tip = Vec3::Zero();                                                    // [m]
  Eigen::Quaternion<Real> orientation = Eigen::Quaternion<Real>::Identity();  // R
  Real jaw = 1;              // opening, 0 closed .. 1 fully open
  std::uint8_t buttons = 0;  // bit i set = button i pressed
};

enum class ToolKind { probe, grasper, scalpel, scope };
std::string_view to_string(ToolKind kind);

struct ToolSpec {
  ToolKind kind = ToolKind::probe;
  int device = 0;                   // which input drives it, >= 0
  Real shaft_length = 0.25;         // [m], > 0
  Real shaft_radius = 0.0025;       // [m], > 0
  tools::ProbeSettings probe;       // the probe's tip, and the scope's (radius: its shaft radius)
  tools::GraspSettings grasp;       // grasper
  Real max_jaw_angle = 0.6;         // grasper: opening at jaw = 1 [rad], in (0, pi)
  Real blade_length = 0.01;         // scalpel [m], > 0
  Real view_angle_degrees = 30;     // scope, in [0, 90)
  Real field_of_view_degrees = 70;  // scope, in (0, 180)
  // The tool stands upright whatever its device's orientation (the palpation block's probes): its
  // shaft runs up, +z, for the probe's slip (tools::Probe::set_shaft), not back along R e_z.
  bool upright = false;
};

// A tool of the given kind driven by device `device`, with the defaults above.
inline ToolSpec make_tool(ToolKind kind, int device = 0) {
  ToolSpec t;
  t.kind = kind;
  t.device = device;
  return t;
}

// A rigid structure (a bone) as a closed surface in the scene frame.
struct BoneSpec {
  std::string name;
  Points vertices;  // #V by 3 [m]
  Triangles triangles;
};

// Local refinement around the tools (TissueBody::refine, bisection.h):
// the tissue is refined to edge_length within radius of a probe's contact and around a grasper's
// jaws as they close, and coarsened again (the splits undone) once no tool has used the region for
// coarsen_after. A split that would make an element need a shorter step than dt is refused, so
// the scene's dt holds.
struct AdaptivitySpec {
  bool enabled = false;
  Real edge_length = 0.004;  // [m], > 0
  Real radius = 0.012;       // [m], > 0
  Real coarsen_after = 0.1;  // [s], >= 0
  int max_splits = 2000;     // per refinement, >= 1
};

// The adaptivity a scene runs with while its session sheds work to keep up with real time
// (server/live/pace_monitor.h), level by level: 0 the spec itself; 1 refinement paused (no new
// splits: max_splits 0, and no region recorded, so a probe still touching when the pause ends is
// refined then; a grasp that closed while paused stays coarse; the tissue refined already stays
// as long as a tool uses it); 2 also the
// refined tissue coarsened as soon as no tool holds it (coarsen_after 0). Levels above 2 act as
// 2. Pausing, rather than refining to a longer edge, is what lightens a tick: a coarser target
// widens the grasper's region by the edge length and refuses fewer splits, and on the station
// liver it made more tets, not fewer.
inline constexpr int kMaxAdaptivityShedLevel = 2;
AdaptivitySpec shed_adaptivity(const AdaptivitySpec& spec, int level);

// A condensed far field (Knee Arthroscopy VR, section VI; sim/models/
// hybrid_condensed_model.h): the scene declares where the surgery happens, a ball (rest) around
// centre; the tets with no node inside it are the far field, linear and condensed to their
// surface and interface nodes, and `model` makes the operational region's model. materials[l] is
// tissue label l's material in the far field (damping: the Kelvin-Voigt time beta [s]). Cuts stay
// inside the ball: a blade whose ends map (rest) to within a guard of its surface ends its stroke
// (cuts_outside_region(); the guard is the longest edge of the operational tets that touch the
// far field, plus 10%). Refinement leaves the far field alone. The nodes are renumbered, the far
// field's first (compactions then keep their numbers, which the condensed model needs).
struct FarFieldSpec {
  bool enabled = false;
  Vec3 centre = Vec3::Zero();  // [m]
  Real radius = 0;             // [m], > 0
  std::vector<ElementMaterial> materials;
};

// A tissue label's toughness: the work to cut a unit area of it (tools/cutting_resistance.h).
struct LabelToughness {
  int label = 0;
  Real toughness = tools::kDefaultToughness;  // [J/m^2], >= 0
};

struct SurgicalSceneSpec {
  TetMesh tissue;           // rest, tets, labels (x, v: the start state, or empty for rest)
  std::vector<char> fixed;  // per tissue node: held (attachments)
  ModelFactory model;       // the tissue's model on a mesh
  std::vector<BoneSpec> bones;
  std::vector<ToolSpec> tools;
  // Damage settings; protected_structures is set to the number of bones (every bone is one).
  tools::DamageSettings damage;
  Real dt = 1e-4;  // [s], > 0
  // The tissue's fastest P-wave speed [m/s] (p_wave_speed of its stiffest material), > 0: the
  // stability guard for slivers (TissueBody).
  Real wave_speed = 3;
  // The models' Kelvin-Voigt damping time beta [s] (scene_run.h: damping * l_min / c for the
  // FEM models), >= 0: the stability guard for slivers includes it.
  Real damping_time = 0;
  // [1/s], >= 0: mass-proportional damping of the tissue's motion, standing for what surrounds
  // it (the abdomen's fluid and neighbouring organs, the joint capsule): a free node's velocity
  // decays as exp(-ambient_damping t). The Kelvin-Voigt damping above acts on strain rates and
  // barely touches an organ's lowest modes: without this, a liver a tool has jerked swings for
  // seconds (and tangles) where a real one settles in a fraction of a second.
  Real ambient_damping = 0;
  Vec3 gravity = Vec3::Zero();  // [m/s^2]
  Real bone_stiffness = 2000;   // penalty of a tool against a bone [N/m], > 0
  int cut_every = 10;           // steps between scalpel updates, >= 1
  int damage_every = 10;        // steps between strain records, >= 1
  // The scalpel's cutting resistance, felt on the hand while its stroke is open
  // (tools/cutting_resistance.h): each stretch of blade in the tissue resists with the toughness
  // of the label of the tet behind the surface face that bounds it (separate structures, the
  // menisci and the ligament, are separate stretches). Labels listed at most once, toughness
  // >= 0; a label not listed has default_toughness (>= 0).
  std::vector<LabelToughness> toughness;
  Real default_toughness = tools::kDefaultToughness;
  tools::CuttingResistanceSettings cutting;
  // The slivers a stroke's cuts leave are collapsed once the stroke ends (Knee Arthroscopy VR,
  // section VII.C), with these settings; min_quality 0 turns it off.
  cut::SimplifyOptions simplify;
  AdaptivitySpec adaptivity;
  FarFieldSpec far_field;
};

enum class EventKind { grasp, release, cut, collision, never_event };
std::string_view to_string(EventKind kind);

struct SceneEvent {
  EventKind kind = EventKind::grasp;
  int tool = -1;       // index into the spec's tools
  Real time = 0;       // [s], at the end of the step it happened in
  std::string detail;  // e.g. "5 vertices", "torn at 1.02 N", "femur"
};

struct ScopeCamera {
  Vec3 eye = Vec3::Zero();
  Vec3 forward = Vec3::UnitZ();  // unit
  Vec3 up = Vec3::UnitY();       // unit, orthogonal to forward
  Real field_of_view_degrees = 70;
};

// The state of one tool for the renderer and the metrics.
struct ToolView {
  ToolKind kind = ToolKind::probe;
  Vec3 tip = Vec3::Zero();         // where the tool is drawn (a probe's proxy)
  Vec3 direction = Vec3::UnitZ();  // d, unit
  Real shaft_length = 0;
  Real shaft_radius = 0;
  bool touching = false;                 // tissue or bone
  Vec3 force_on_tissue = Vec3::Zero();   // a probe's or scope's push on the tissue [N]
  std::optional<collide::JawPair> jaws;  // grasper
  // A scalpel's blade length in the tissue while its stroke is open [m].
  Real blade_depth = 0;
  // For drawing the working end: R e_x (the jaws' opening plane, the blade's flat), the probe's
  // radius, the jaws' opening [rad] and length, the blade's length [m].
  Vec3 side = Vec3::UnitX();
  bool has_input = false;  // false until its device has reported (the pose is then meaningless)
  Real tip_radius = 0;
  Real jaw_angle = 0;
  Real jaw_length = 0;
  Real blade_length = 0;
};

class SurgicalScene {
 public:
  // Throws std::invalid_argument for a bad spec (naming the field), or as TissueBody, the tools,
  // the bones and the damage tracker do.
  explicit SurgicalScene(SurgicalSceneSpec spec);
  ~SurgicalScene();
  SurgicalScene& operator=(const SurgicalScene&) = delete;
  // A deep copy of the whole scene (tissue, model, cutters, tools, damage, events; the bones'
  // fixed geometry is shared): stepped with the same inputs it stays equal to the original bit
  // for bit. A checkpoint for replays' seeks.
  std::unique_ptr<SurgicalScene> clone() const;

  // One step of dt. inputs[d] drives device d's tools; a tool whose device has no input (d >=
  // inputs.size()) stays where it was. Throws std::invalid_argument for a non-finite input.
  void step(std::span<const ToolInput> inputs);

  Real time() const { return time_; }
  std::int64_t steps() const { return steps_; }
  const TissueBody& tissue() const { return *tissue_; }
  int num_tools() const;
  ToolView tool_view(int tool) const;
  // What device's station agent renders: the sum over the device's tools of their local force
  // models at the device position (F0 on the hand, K symmetric PSD).
  tools::LocalForceModel force_model(int device) const;
  // The first scope's camera, if the scene has a scope with an input.
  std::optional<ScopeCamera> scope_camera() const;
  // The events since the last call.
  std::vector<SceneEvent> take_events();
  tools::DamageMetrics damage() const { return damage_->metrics(); }
  const tools::DamageTracker& damage_tracker() const { return *damage_; }
  // Whether every tissue position and velocity is finite.
  bool state_finite() const;
  // Scalpel updates refused because the tet at the blade's tip was squashed or inverted (the cut
  // waits for the tissue there to recover; the stroke stays open while the blade is in the
  // tissue).
  int cuts_refused() const { return cuts_refused_; }
  // Strain records skipped because a strain was not finite (a running-away state).
  int strain_records_skipped() const { return strain_records_skipped_; }
  // Tissue left inside out recovers: once some tet has stayed inverted for kRecoverAfterS, each
  // step the inverted tets clear of every tool (kRecoverWorkReach from one that works the tissue,
  // kRecoverClearance beyond the tip ball, jaws or blade of any other) pull toward their rest
  // shapes (TissueBody::recover_inverted), dt / kRecoverTimeS of the way: a tangle relaxes with a
  // time constant of kRecoverTimeS. One that outlasts that (held inside out against a bone) is
  // pulled twice as hard for every kRecoverDoublingS it has been pulled, up to a full projection
  // onto the rest shape each step. Nodes a grasper holds stay where it holds them. A tet inverted
  // under a tool is left to the tool's contact. The pulls so far (a tet pulled on ten steps counts
  // ten): a metric, the price of not leaving a tangle in the tissue.
  std::int64_t inverted_tets_pulled() const { return inverted_tets_pulled_; }
  static constexpr Real kRecoverAfterS = 0.05;
  static constexpr Real kRecoverTimeS = 0.02;
  static constexpr Real kRecoverDoublingS = 0.05;
  static constexpr Real kRecoverClearance = 0.0005;  // [m]
  static constexpr Real kRecoverWorkReach = 0.02;    // [m]
  // Edge collapses made by the simplification after strokes (spec.simplify).
  int collapses() const { return collapses_; }
  // Adaptivity (spec.adaptivity): edges split, splits refused (an edge left long because a split
  // would have made a sliver or needed a shorter step), splits undone by coarsening, and the
  // regions kept refined now.
  int splits() const { return splits_; }
  int splits_refused() const { return splits_refused_; }
  int splits_undone() const { return splits_undone_; }
  int refined_regions() const { return static_cast<int>(regions_.size()); }
  // The shedding level of the adaptivity from the next step on (shed_adaptivity), clamped to
  // 0 .. kMaxAdaptivityShedLevel. Part of the state: a clone keeps it, and a replay sets it per
  // tick as the session did.
  void set_shed_level(int level);
  int shed_level() const { return shed_level_; }
  // Scalpel updates refused because the blade reached the condensed far field (spec.far_field).
  int cuts_outside_region() const { return cuts_outside_region_; }

 private:
  struct Tool;

  // Member-wise (the ClonePtrs copy deeply); clone() then rebinds the cutters to the copy's mesh.
  SurgicalScene(const SurgicalScene&);

  void cut(Tool& tool, int index);
  // After the step: TissueBody::recover_inverted clear of the tools, once inverted tets have
  // lasted kRecoverAfterS.
  void recover_inverted();
  // The scalpel's cutting resistance this step (tool.cutting_force), from the blade's depth in
  // the tissue and the tip's motion over the step; zero unless its stroke is open.
  void resist_cut(Tool& tool);
  Real toughness(int label) const;
  // Whether the blade (a, b) reaches within far_guard_ of the far field (rest configuration).
  bool blade_outside_region(const Vec3& a, const Vec3& b) const;
  // After a stroke: the slivers among the tets its complete cuts changed are collapsed
  // (TissueBody::simplify), unless another stroke is open or a grasper holds.
  void simplify_after_stroke(Tool& tool);
  // The jaws' pose for this step (Grasper::set_jaws, first in a step): release events.
  void set_jaws(Tool& tool, int index);
  void grasp(Tool& tool, int index);
  // Refines around touching probes and closing graspers, coarsens regions no tool has used for
  // spec.adaptivity.coarsen_after (nothing while a stroke is open; no coarsening while a
  // grasper holds or closes, node numbers change, nor while a probe or scope touches).
  void adapt();
  void refine(int tool, const Vec3& centre, Real radius);
  void coarsen();
  // The damage tracker's slots after the tissue's tets changed (slots `changed`, each inheriting
  // the state of parents[k], or none if parents is empty).
  void update_damage(int tets_before, std::span<const int> changed, std::span<const int> parents);
  // The damage tracker's slots, the cutters and the pending stroke regions after a compaction
  // (tet_map: old slot -> new or -1).
  void after_compaction(std::span<const int> tet_map, int slots_before);
  void bones(Tool& tool, int index);
  void after_topology_change(int tets_before, std::span<const int> changed);
  // The per-node arrays (prescribed rows, surface nodes) follow the tissue's node count.
  void follow_node_count();
  void event(EventKind kind, int tool, std::string detail);
  // Nodes below this index keep their numbers through cut frames (the scalpels' committed nodes).
  int stable_nodes() const;

  SurgicalSceneSpec spec_;
  ClonePtr<TissueBody> tissue_;
  // Fixed after construction: shared by clones (FCL's trees are costly to copy).
  std::shared_ptr<const std::vector<collide::RigidBody>> bones_;
  std::vector<Tool> tools_;
  ClonePtr<tools::DamageTracker> damage_;
  Prescribed prescribed_;
  std::vector<int> prescribed_rows_;  // rows of prescribed_.mask set by the last step
  std::vector<int> surface_nodes_;
  std::vector<Real> bone_depths_;
  std::vector<char> bone_touching_;
  std::vector<SceneEvent> events_;
  std::vector<char> damage_alive_;
  Real time_ = 0;
  Real strain_time_ = 0;  // since the last strain record
  std::int64_t steps_ = 0;
  int cuts_refused_ = 0;
  int shed_level_ = 0;
  int strain_records_skipped_ = 0;
  std::int64_t inverted_tets_pulled_ = 0;
  // The recovery's clocks [s]: the tissue with an inverted tet, and pulling it, since a tangle
  // began; since the tissue last had an inverted tet.
  Real inverted_time_ = 0;
  Real pulling_time_ = 0;
  Real clean_time_ = 0;
  std::vector<TissueBody::Segment> tool_segments_;  // recover_inverted's scratch
  int collapses_ = 0;
  struct Region {
    Vec3 centre = Vec3::Zero();  // rest [m]
    Real radius = 0;
    Real last_used = 0;  // [s]
    int tool = -1;
  };
  std::vector<Region> regions_;
  int splits_ = 0;
  int splits_refused_ = 0;
  int splits_undone_ = 0;
  Real far_guard_ = 0;  // > 0 with a far field (FarFieldSpec)
  int cuts_outside_region_ = 0;
};

}  // namespace incise::sim::surgery
