#pragma once
// The deterministic heart of a session, shared by live runs and replays: a scene's simulation plus
// the tool, advanced one tick (e.g. 2 ms) per device input. Within a tick the tool tip moves
// linearly from its previous position to the input's, and every sub-step (the scene's solver.dt)
// applies the sphere-tip penalty contact. Same scene + same inputs = same state, bit for bit.
#include <cstdint>
#include <memory>
#include <string>

#include "devices/device_state.h"
#include "devices/protocol.h"
#include "server/live/snapshot.h"
#include "sim/interact/tool_contact.h"
#include "sim/mesh/boundary_surface.h"
#include "sim/scene/scene.h"
#include "sim/scene/simulation.h"

namespace incise::server::live {

// Running sums over the ticks taken, for the live metrics (the score comes from the recording).
struct RunningMetrics {
  double path_length_m = 0;
  double peak_force_n = 0;
  double force_squared_time = 0;  // integral of |F|^2 dt [N^2 s]
  std::int64_t contact_ticks = 0;
};

class SimEngine {
 public:
  // tick_s: the tick length [s]; must be a whole number of the scene's solver.dt (within 1e-9).
  // Throws sim::SceneError for an invalid scene and std::invalid_argument for a bad tick.
  SimEngine(const sim::Scene& scene, double tick_s);

  // Advances one tick with the tool tip at input.position at its end.
  void tick(const devices::DeviceState& input);

  double tick_s() const { return tick_s_; }
  int substeps() const { return substeps_; }
  std::int64_t ticks() const { return ticks_; }
  double time_s() const { return static_cast<double>(ticks_) * tick_s_; }
  const sim::Simulation& simulation() const { return simulation_; }
  const sim::BoundarySurface& surface() const { return surface_; }
  const sim::SphereTool& tool() const { return tool_; }
  const sim::Vec3& tool_tip() const { return tip_; }
  const devices::DeviceState& last_input() const { return last_input_; }
  // The contact at the end of the last tick: reaction on the tool and its linearisation.
  const sim::ToolContact& contact() const { return contact_; }
  const RunningMetrics& metrics() const { return metrics_; }
  // Force model for the agent from the last tick (force clamped to kMaxForceN).
  devices::ForceModel force_model() const;
  // Whether the state is finite (the engine resets nothing silently: the session reports it).
  bool state_finite() const { return simulation_.state_finite(); }

  struct Checkpoint {
    sim::SimulationState simulation;
    sim::Vec3 tip;
    bool has_input = false;
    devices::DeviceState last_input;
    sim::ToolContact contact;
    RunningMetrics metrics;
    std::int64_t ticks = 0;
  };
  Checkpoint checkpoint() const;
  void restore(const Checkpoint& checkpoint);

  // FNV-1a over the bytes of every node position: equal hashes = equal states (for replays).
  std::string state_hash() const;

  // Force sent to the hand is clamped to this magnitude [N]: a safety limit, far above what
  // palpation needs.
  static constexpr double kMaxForceN = 20.0;

 private:
  sim::Simulation simulation_;
  sim::BoundarySurface surface_;
  sim::SphereTool tool_;
  double tick_s_;
  int substeps_;
  sim::Points node_forces_;
  sim::Vec3 tip_;
  bool has_input_ = false;
  devices::DeviceState last_input_;
  sim::ToolContact contact_;
  RunningMetrics metrics_;
  std::int64_t ticks_ = 0;
};

// The engine's current state as an immutable snapshot for the renderer and the viewers.
std::shared_ptr<Snapshot> make_snapshot(const SimEngine& engine,
                                        std::shared_ptr<const sim::BoundarySurface> surface);

// Where the tool waits before the device has reported: well above any scene, out of contact.
inline constexpr double kParkedToolHeight = 1.0;

}  // namespace incise::server::live
