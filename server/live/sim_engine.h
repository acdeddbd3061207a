#pragma once
// The deterministic heart of a session, shared by live runs and replays: a scene's simulation plus
// one tool per hand (a station has one or two devices; the task's tools[i] is held by device i),
// advanced one tick (e.g. 2 ms) per device input. Same scene + same inputs = same state, bit for
// bit. Every scene runs on one runtime, a surgical scene (session_scene.h, surgery_world.h): the
// scene's own tools (probe, grasper, scalpel, scope; the palpation block's probes) follow their
// devices' inputs, moving linearly within a tick, and the scene cuts, grasps and refines.
#include <array>
#include <cstdint>
#include <memory>
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

namespace incise::server::live {

// Where the tool waits before the device has reported: well above any scene, out of contact.
inline constexpr double kParkedToolHeight = 1.0;

// Running sums over the ticks taken, for the live metrics (the score comes from the recording).
struct RunningMetrics {
  double path_length_m = 0;
  double peak_force_n = 0;
  double force_squared_time = 0;  // integral of |F|^2 dt [N^2 s]
  std::int64_t contact_ticks = 0;
};

class SimEngine {
 public:
  // tick_s: the tick length [s] (a whole number of the scene's steps: its dt is shortened to fit,
  // surgery_world.h). hands: 1 or kMaxHands tools. Throws std::invalid_argument for a bad tick or
  // hand count.
  SimEngine(const SessionScene& scene, double tick_s, int hands = 1);

  static constexpr int kMaxHands = 2;

  // Advances one tick with the tool tip at input.position at its end (hand 0 only).
  void tick(const devices::DeviceState& input);
  // Advances one tick with hand i's tool at inputs[i].position; inputs.size() == hands().
  void tick(std::span<const devices::DeviceState> inputs);
  int hands() const { return hands_; }
  // The physics' shedding level from the next tick on, 0 .. sim::surgery::
  // kMaxAdaptivityShedLevel (the scene's adaptivity, sim/surgery/surgical_scene.h; clamped): a
  // live session sets it as it falls behind real time, and records it per tick so that a replay
  // sets it as the session did.
  void set_shed_level(int level) { world_->set_shed_level(level); }
  int shed_level() const { return world_->scene().shed_level(); }

  double tick_s() const { return tick_s_; }
  int substeps() const { return world_->substeps(); }
  std::int64_t ticks() const { return ticks_; }
  double time_s() const { return static_cast<double>(ticks_) * tick_s_; }
  // The scene and its tools.
  const SurgeryWorld& world() const { return *world_; }
  // Every tissue node's current position [m] (#nodes by 3; the count changes with cuts and
  // refinement).
  const sim::Points& positions() const;
  // The tissue's boundary for the renderer; a new object only when the topology changed.
  std::shared_ptr<const sim::BoundarySurface> surface() const;
  // The radius of hand i's probe tip, what the renderer draws at the tip (a hand without a probe:
  // sim::SphereTool's default, 5 mm).
  double tool_radius(int hand = 0) const;
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
  // Every damage metric (sim/tools/damage_metrics.h): the tissue's strain damage, the cuts
  // against the marked line and the never events.
  sim::tools::DamageMetrics damage() const;
  // Whether the state is finite (the engine resets nothing silently: the session reports it).
  bool state_finite() const;
  // The scene's events so far (grasps, cuts, collisions, never events).
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
    std::array<Hand, kMaxHands> hands;
    RunningMetrics metrics;
    std::int64_t ticks = 0;
    // The world, whole (SurgicalScene::clone), and its events so far.
    std::shared_ptr<const SurgeryWorld> world;
    SceneEventLog scene_events;
  };
  // Any tick; restore() makes the state bit for bit what it was, and the checkpoint stays valid
  // (for restoring again). Throws std::invalid_argument for a checkpoint without a world.
  Checkpoint checkpoint() const;
  void restore(const Checkpoint& checkpoint);

  // FNV-1a over the bytes of every node position: equal hashes = equal states (for replays).
  std::string state_hash() const;

  // Force sent to the hand is clamped to this magnitude [N]: a safety limit, far above what
  // palpation needs.
  static constexpr double kMaxForceN = 20.0;

 private:
  std::unique_ptr<SurgeryWorld> world_;
  double tick_s_ = 0;
  int hands_ = 1;
  std::array<Hand, kMaxHands> hand_;
  RunningMetrics metrics_;
  std::int64_t ticks_ = 0;
  SceneEventLog scene_events_;
};

// The engine's current state as an immutable snapshot for the renderer and the viewers.
std::shared_ptr<Snapshot> make_snapshot(const SimEngine& engine);

}  // namespace incise::server::live
