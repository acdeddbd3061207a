#pragma once
// The deterministic heart of a session, shared by live runs and replays: a scene's simulation plus
// one tool per hand (a station has one or two devices; the task's tools[i] is held by device i),
// advanced one tick (e.g. 2 ms) per device input. Same scene + same inputs = same state, bit for
// bit. Two kinds of scene (session_scene.h):
//   a sim core scene (the palpation block): within a tick each tool tip moves linearly from its
//     previous position to its input's, and every sub-step (the scene's solver.dt) applies the
//     sphere-tip penalty contacts of both;
//   a surgical scene (liver, knee): the scene's own tools (probe, grasper, scalpel, scope) follow
//     their devices' inputs, and the scene cuts, grasps and refines (surgery_world.h).
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "devices/device_state.h"
#include "devices/protocol.h"
#include "server/live/scene_event_log.h"
#include "server/live/session_scene.h"
#include "server/live/snapshot.h"
#include "server/live/surgery_world.h"
#include "sim/interact/tool_contact.h"
#include "sim/mesh/boundary_surface.h"
#include "sim/scene/scene.h"
#include "sim/scene/simulation.h"
#include "sim/tools/damage_tracker.h"

namespace incise::server::live {

// Where the tool waits before the device has reported: well above any scene, out of contact.
inline constexpr double kParkedToolHeight = 1.0;

// Tissue damage from the simulation (sim/tools/damage_tracker.h, docs/damage.md): every
// kDamageEvery ticks the largest principal Green strain of every tet; a tet strained beyond
// kDamageStrain is damaged for good. Read only: it never changes the simulated state.
inline constexpr int kDamageEvery = 5;        // 100 Hz at 500 Hz ticks
inline constexpr double kDamageStrain = 0.4;  // [-] the liver preset's threshold (scene_presets.h)

// Running sums over the ticks taken, for the live metrics (the score comes from the recording).
struct RunningMetrics {
  double path_length_m = 0;
  double peak_force_n = 0;
  double force_squared_time = 0;  // integral of |F|^2 dt [N^2 s]
  std::int64_t contact_ticks = 0;
};

class SimEngine {
 public:
  // tick_s: the tick length [s]; for a sim core scene it must be a whole number of the scene's
  // solver.dt (within 1e-9). hands: 1 or kMaxHands tools. Throws sim::SceneError for an invalid
  // scene and std::invalid_argument for a bad tick or hand count.
  SimEngine(const SessionScene& scene, double tick_s, int hands = 1);

  static constexpr int kMaxHands = 2;

  // Advances one tick with the tool tip at input.position at its end (hand 0 only).
  void tick(const devices::DeviceState& input);
  // Advances one tick with hand i's tool at inputs[i].position; inputs.size() == hands().
  void tick(std::span<const devices::DeviceState> inputs);
  int hands() const { return hands_; }

  double tick_s() const { return tick_s_; }
  int substeps() const { return substeps_; }
  std::int64_t ticks() const { return ticks_; }
  double time_s() const { return static_cast<double>(ticks_) * tick_s_; }
  // The sim core scene's simulation; precondition: !surgery().
  const sim::Simulation& simulation() const { return *simulation_; }
  // The surgical scene, or nullptr for a sim core scene.
  const SurgeryWorld* surgery() const { return surgery_.get(); }
  // Every tissue node's current position [m] (#nodes by 3; a surgical scene's count changes with
  // cuts and refinement).
  const sim::Points& positions() const;
  // The tissue's boundary for the renderer; a new object only when the topology changed.
  std::shared_ptr<const sim::BoundarySurface> surface() const;
  // The sphere tool of a sim core scene (its tip radius is what the renderer draws).
  const sim::SphereTool& tool() const { return tool_; }
  const sim::Vec3& tool_tip(int hand = 0) const { return hand_[hand].tip; }
  const devices::DeviceState& last_input(int hand = 0) const { return hand_[hand].last_input; }
  // The contact at the end of the last tick: reaction on the tool and its linearisation.
  const sim::ToolContact& contact(int hand = 0) const { return hand_[hand].contact; }
  // Of hand 0, the primary hand (the score's path length and forces); see hand_path_length_m.
  const RunningMetrics& metrics() const { return metrics_; }
  double hand_path_length_m(int hand) const { return hand_[hand].path_length_m; }
  // Force model for hand i's device from the last tick (force clamped to kMaxForceN).
  devices::ForceModel force_model(int hand = 0) const;
  // The simulation's tissue damage so far: damaged rest volume over the tissue's, and the largest
  // principal Green strain any tet reached.
  double damage_index() const { return damage().damage_index; }
  double peak_strain() const { return damage().peak_strain; }
  // Every damage metric (sim/tools/damage_metrics.h): a surgical scene's include its cuts against
  // the marked line and its never events.
  sim::tools::DamageMetrics damage() const;
  // Whether the state is finite (the engine resets nothing silently: the session reports it).
  bool state_finite() const;
  // A surgical scene's events so far (grasps, cuts, collisions, never events); none for a sim
  // core scene.
  const SceneEventLog& scene_events() const { return scene_events_; }

  // One hand's tool: where it is and what it touches.
  struct Hand {
    sim::Vec3 tip = sim::Vec3(0, 0, kParkedToolHeight);
    bool has_input = false;
    devices::DeviceState last_input;
    sim::ToolContact contact;
    double path_length_m = 0;
  };
  struct Checkpoint {
    sim::SimulationState simulation;
    std::array<Hand, kMaxHands> hands;
    RunningMetrics metrics;
    std::int64_t ticks = 0;
    std::shared_ptr<const sim::tools::DamageTracker> damage;
    // A surgical scene's world, whole (SurgicalScene::clone), and its events so far.
    std::shared_ptr<const SurgeryWorld> surgery;
    SceneEventLog scene_events;
  };
  // Any tick, any scene; restore() makes the state bit for bit what it was, and the checkpoint
  // stays valid (for restoring again).
  Checkpoint checkpoint() const;
  void restore(const Checkpoint& checkpoint);

  // FNV-1a over the bytes of every node position: equal hashes = equal states (for replays).
  std::string state_hash() const;

  // Force sent to the hand is clamped to this magnitude [N]: a safety limit, far above what
  // palpation needs.
  static constexpr double kMaxForceN = 20.0;

 private:
  std::optional<sim::Simulation> simulation_;
  std::unique_ptr<SurgeryWorld> surgery_;
  std::shared_ptr<const sim::BoundarySurface> surface_;  // of the sim core scene
  sim::SphereTool tool_;
  double tick_s_ = 0;
  int substeps_ = 1;
  int hands_ = 1;
  sim::Points node_forces_;
  std::array<Hand, kMaxHands> hand_;
  RunningMetrics metrics_;
  std::int64_t ticks_ = 0;
  std::optional<sim::tools::DamageTracker> damage_;  // of the sim core scene
  SceneEventLog scene_events_;
};

// The engine's current state as an immutable snapshot for the renderer and the viewers.
std::shared_ptr<Snapshot> make_snapshot(const SimEngine& engine);

}  // namespace incise::server::live
