#pragma once

// The stability suite of the surgical scenes: seeded random tool scripts played on the liver and
// knee scenes (sim/surgery/scene_presets.h), each run checked for what a long session must never
// show: an exception, a non-finite state, an inverted element left once the tools are gone, a mesh
// that keeps growing. Shared by the CI test (surgical_scene_stability_test.cpp) and the long runner
// (stability_main.cpp, `surgery_stability`); docs/surgery_stability.md has the figures.
//
// A sequence is one script per device (each scene has one tool per device). A script is a list of
// segments, each a list of moves the device's input follows:
//   probe     approach a target, press in to a random depth, hold, drag, withdraw;
//   grasp     approach open, close, pull in a random direction, then release or tear (a fast
//             pull far beyond the tear force), withdraw;
//   cut       a scalpel stroke at a random depth along the marked line or a random line through a
//             target; cross_cut: a stroke across the previous one (or the marked line);
//   jerk      violent jumps of the tip within one step (up to max_jerk, the orientation turned
//             too), often from inside the tissue;
//   sweep     a fast pass through the tissue at up to max_speed;
//   retreat   back to where the tool enters, and a pause.
// Tools come in from above (liver: a cone around -z) or through their portal (knee: scope and
// probe through their own, the scalpel through the anteromedial one). Everything a sequence does
// follows from its seed: a failure is replayed with `surgery_stability --seed S --sequences 1`.

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "sim/core/types.h"
#include "sim/surgery/scene_presets.h"
#include "sim/surgery/surgical_scene.h"

namespace incise::sim::surgery::stability {

// The scenes at coarse resolution (liver cell 10 mm, knee tissue cell 4 mm) with three tools:
// liver probe (device 0), grasper (1), scalpel (2); knee scope (0), probe (1), scalpel (2).
// name is "liver" or "knee"; throws std::invalid_argument for another name.
SurgicalSceneSetup stability_scene(std::string_view name);

// What the generator needs to know about a scene.
struct SceneGeometry {
  std::string name;
  std::vector<ToolKind> tools;  // per device
  Real dt = 0;                  // the scene's step [s]
  std::vector<Vec3> targets;    // landmarks and tissue surface points to aim at [m]
  std::vector<Vec3> cut_line;   // the marked cut line [m], >= 2 points
  // Per device: the portal a tool enters through (knee), or empty: tools come from above.
  std::vector<Portal> entries;
  Vec3 up = Vec3::UnitZ();   // unit: "above" for tools without a portal
  Vec3 home = Vec3::Zero();  // where tools rest, away from the tissue and bones [m]
};

// The geometry of a setup: targets are its landmarks, its cut target and (every few) tissue
// surface nodes; home is 3 cm above the tissue's bounding box.
SceneGeometry geometry_of(const SurgicalSceneSetup& setup);

enum class SegmentKind { probe, grasp, cut, cross_cut, jerk, sweep, retreat };
inline constexpr int kSegmentKinds = 7;
std::string_view to_string(SegmentKind kind);

// One move of a device's input: from where the previous move ended to here over `steps` steps,
// linearly (the orientation by slerp), or, for a jump, here at the first step and held.
struct Move {
  int steps = 1;  // >= 1
  Vec3 tip = Vec3::Zero();
  Eigen::Quaternion<Real> orientation = Eigen::Quaternion<Real>::Identity();
  Real jaw = 1;
  bool jump = false;
  int segment = -1;  // index into DeviceScript::segments
};

struct DeviceScript {
  ToolKind kind = ToolKind::probe;
  ToolInput start;  // the input before the first move
  // Where the tool is taken after the sequence [m]: home (liver), or out of the knee through its
  // portal, kOutOfPortal behind it (a tool resting in its portal still touches what a cut set
  // loose there).
  Vec3 out = Vec3::Zero();
  static constexpr Real kOutOfPortal = 0.03;  // [m]
  std::vector<Move> moves;
  std::vector<SegmentKind> segments;  // what the moves do, in order (for the report)
};

struct GeneratorSettings {
  int steps = 1500;        // the sequence's length in steps, >= 1
  Real max_jerk = 0.05;    // the largest jump of a tip within one step [m]
  Real max_speed = 2;      // the fastest sweep [m/s]
  Real max_press = 0.012;  // the deepest press past a target [m]
  Real approach = 0.015;   // how far before a target an approach starts [m]
  // Task speeds (press, stroke, pull, drag: a hand's 2-50 cm/s) are multiplied by this, capped
  // at max_speed: the knee's step is ~10 us, so at a hand's pace a sequence of thousands of steps
  // would not finish one stroke (default_generator: 10 for the knee).
  Real speed_scale = 1;
};

struct Sequence {
  std::uint64_t seed = 0;
  int steps = 0;
  std::vector<DeviceScript> devices;  // one per entry of SceneGeometry::tools
};

// The scene's steps per sequence and task speed scale: liver 1500 steps at 1, knee 6000 at 10
// (its step is 20 times shorter).
GeneratorSettings default_generator(std::string_view scene);

// A random sequence: the same seed and settings give the same sequence.
// Throws std::invalid_argument for settings out of range or a geometry without targets.
Sequence make_sequence(const SceneGeometry& geometry, std::uint64_t seed,
                       const GeneratorSettings& settings);

// Plays a script: the device's input at each step; past its end, the last input.
class ScriptPlayer {
 public:
  explicit ScriptPlayer(const DeviceScript& script);
  ToolInput next();
  // The segment the last input belongs to (-1 before the first or past the end).
  int segment() const;

 private:
  const DeviceScript* script_;
  ToolInput from_;  // where the current move started
  std::size_t move_ = 0;
  int step_ = 0;  // steps done of the current move
};

// After the sequence every tool is opened and taken out (DeviceScript::out) over retract_steps;
// then the tissue is left alone for at least settle_min_steps and settle_min_time, and until no
// element is inverted (checked every 50 steps), at most settle_max_steps or settle_max_time,
// whichever is longer: an element still inverted then is a failure. (The time: the knee's step is a
// sixth of the liver's, and 6,000 of its steps are 0.19 s.)
struct RunSettings {
  int retract_steps = 100;
  int settle_min_steps = 300;
  Real settle_min_time = 0.01;  // [s]
  int settle_max_steps = 6000;
  Real settle_max_time = 1.2;  // [s]
  Real max_growth = 8;  // peak tets / initial tets above this is a failure (unbounded growth)
  int trace_every = 0;  // > 0: a line to stderr every this many steps (surgery_stability --trace)
};

inline constexpr int kEventKinds = 5;  // EventKind's values

struct SequenceResult {
  std::string scene;
  std::uint64_t seed = 0;
  bool passed = false;
  std::string failure;   // why not, with the step
  int steps = 0;         // sequence steps run
  int settle_steps = 0;  // retract and settle steps run
  int peak_inverted = 0;
  int inverted_at_end = -1;
  // The largest node speed after settling [m/s]: reported, not judged (the scenes' Kelvin-Voigt
  // damping leaves the lowest modes ringing for seconds).
  Real speed_at_end = 0;
  int initial_tets = 0, peak_tets = 0, final_tets = 0;
  int initial_nodes = 0, peak_nodes = 0;
  int cuts_refused = 0;
  std::int64_t inverted_tets_pulled = 0;  // SurgicalScene::inverted_tets_pulled: tangles recovered
  int peak_mass_scaled_nodes = 0;
  Real max_mass_scale = 1;     // the largest at any step (slivers of an open stroke included)
  Real mass_scale_at_end = 1;  // after the strokes' simplification and the settle
  int collapses = 0;           // edge collapses of the simplification after strokes
  int splits = 0;              // edge bisections of the refinement around tools
  int splits_undone = 0;       // ... undone by coarsening
  std::array<int, kEventKinds> events{};
  std::array<int, kSegmentKinds> segments{};
  double seconds = 0;  // wall time
};

// Runs one sequence on a fresh scene made from spec, then retracts every tool and lets the tissue
// settle. Never throws: an exception is a failure of the result.
SequenceResult run_sequence(const SurgicalSceneSpec& spec, const std::string& scene,
                            const Sequence& sequence, const RunSettings& settings);

// This process's resident set size [KiB] (VmRSS of /proc/self/status), or -1 if unknown.
long resident_kib();

}  // namespace incise::sim::surgery::stability
