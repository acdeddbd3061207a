#pragma once
// What a session publishes for the renderer and the viewers: an immutable picture of one instant.
// The simulation thread builds a new one at the snapshot rate (~60 Hz) and swaps a shared_ptr;
// readers keep theirs as long as they need it, so nobody waits on the simulation.
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "sim/core/types.h"
#include "sim/mesh/boundary_surface.h"
#include "sim/surgery/surgical_scene.h"

namespace incise::server::live {

struct Snapshot {
  std::int64_t tick = 0;
  double sim_time_s = 0;
  std::shared_ptr<const sim::BoundarySurface> surface;  // changes only with the topology
  // Per face of surface, 1 for a wall a cut opened (sim/surgery/cut_walls.h); null for the
  // palpation block, which nothing cuts.
  std::shared_ptr<const std::vector<std::uint8_t>> cut_faces;
  // Per face of surface, its tissue label; per surface vertex, its rest position (SurgeryWorld).
  std::shared_ptr<const std::vector<std::uint8_t>> face_labels;
  std::shared_ptr<const sim::Points> surface_rest;
  // A surgical scene's instruments as simulated (every tool but a scope, which is the camera),
  // drawn with their working ends; empty for the palpation block, whose probes are drawn from the
  // hand fields below.
  std::vector<sim::surgery::ToolView> instruments;
  // The scope's camera, when the scene has a scope on a device that has reported.
  std::optional<sim::surgery::ScopeCamera> scope;
  sim::Points positions;  // #nodes by 3 [m]
  sim::Vec3 tool_tip = sim::Vec3::Zero();
  double tool_radius = 0.005;
  bool contact = false;
  sim::Vec3 force_n = sim::Vec3::Zero();  // on the tool
  int hands = 1;                          // tools in the scene (a two-handed task has 2)
  sim::Vec3 second_tool_tip = sim::Vec3::Zero();
  sim::Vec3 second_force_n = sim::Vec3::Zero();
  // From each tool's tip back along its shaft, unit (from the device's orientation; the
  // palpation block's probes stand upright).
  std::array<sim::Vec3, 2> shaft_direction = {sim::Vec3::UnitZ(), sim::Vec3::UnitZ()};
  // The marked cut line's points as the tissue carries them now (if the scene has one), for the
  // renderer to draw as ink dots.
  std::vector<sim::Vec3> marks;
  double peak_force_n = 0;
  double path_length_m = 0;
  double damage_index = 0;  // the simulation's damaged tissue volume fraction (SimEngine)
  double peak_strain = 0;   // the largest principal Green strain so far [-]
  // The cuts of a scene that has them (cutting: every scene but the palpation block): their area
  // (rest, one side) and mean distance to the marked line, and whether a protected structure was
  // cut (a never event).
  bool cutting = false;
  double cut_area_m2 = 0;
  double cut_mean_distance_m = 0;
  bool never_event = false;
  // Pulls of tissue left inside out back toward its rest shape (SurgicalScene::
  // inverted_tets_pulled): the simulation recovering a tangle clear of the tools.
  std::int64_t inverted_tets_pulled = 0;
  std::chrono::steady_clock::time_point published_at;
};

// The last few frame latencies (snapshot published -> frame handed to the socket) [ms].
class LatencyWindow {
 public:
  void add(double ms) {
    std::lock_guard lock(mutex_);
    values_[next_++ % values_.size()] = ms;
    count_ = std::min(count_ + 1, values_.size());
  }
  // Median of the window, or -1 when empty.
  double median() const {
    std::lock_guard lock(mutex_);
    if (count_ == 0) return -1;
    std::array<double, 128> sorted;
    std::copy_n(values_.begin(), count_, sorted.begin());
    std::nth_element(sorted.begin(), sorted.begin() + count_ / 2, sorted.begin() + count_);
    return sorted[count_ / 2];
  }

 private:
  mutable std::mutex mutex_;
  std::array<double, 128> values_{};
  std::size_t next_ = 0;
  std::size_t count_ = 0;
};

// One session as the viewers see it: its latest snapshot and its status.
class StreamSource {
 public:
  virtual ~StreamSource() = default;
  virtual std::shared_ptr<const Snapshot> snapshot() const = 0;
  // Status fields of the metrics message: "state", "reason", "agent_online", "sim_rate_hz", ...
  virtual nlohmann::json status() const = 0;
  // Frame latencies the viewers measured; the median shows in the status as frame_latency_ms.
  LatencyWindow& frame_latency() const { return frame_latency_; }

 private:
  mutable LatencyWindow frame_latency_;
};

// A shared_ptr slot one thread writes and others read.
class SnapshotSlot {
 public:
  void publish(std::shared_ptr<const Snapshot> snapshot) {
    std::lock_guard lock(mutex_);
    latest_ = std::move(snapshot);
  }
  std::shared_ptr<const Snapshot> latest() const {
    std::lock_guard lock(mutex_);
    return latest_;
  }

 private:
  mutable std::mutex mutex_;
  std::shared_ptr<const Snapshot> latest_;
};

}  // namespace incise::server::live
