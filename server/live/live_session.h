#pragma once
// One running session (docs/architecture.md, "A live session, end to end"): on its own thread it
// steps the SimEngine at a fixed tick rate in real time from the station agent's latest device
// state, sends the agent the local force model, publishes snapshots for the viewers and records
// every tick's input to SQLite.
//
// States and transitions:
//   running --pause()/agent drops--> paused --resume() (agent online)--> running
//   running | paused --stop()--> finished   (recording closed, score stored)
// While paused the simulation does not advance and nothing is recorded, so the recording is a
// gap-free sequence of ticks and a replay needs no notion of pauses.
//
// The session thread owns its own SQLite connection (WAL allows it beside the server's) and is
// the only writer of its session's rows after the start, so control calls never wait on the
// database and the REST handlers' lock never waits on the simulation.
#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "curriculum/curriculum.h"
#include "db/database_url.h"
#include "devices/device_state.h"
#include "devices/protocol.h"
#include "server/live/frame_streamer.h"
#include "server/live/pace_monitor.h"
#include "server/live/session_scene.h"
#include "server/live/sim_engine.h"
#include "server/live/snapshot.h"
#include "sim/scene/scene.h"

namespace incise::server::live {

struct LiveSessionParams {
  std::int64_t session_id = 0;
  std::int64_t station_id = 0;
  std::int64_t recording_id = 0;
  std::optional<SessionScene> scene;  // required
  curriculum::Task task;
  db::DatabaseUrl database;     // the session thread opens its own connection
  double tick_hz = 500;         // simulation ticks per second of real time
  double force_model_hz = 500;  // local force models sent to the agent (every tick at 500 Hz)
  double snapshot_hz = 125;     // snapshots for rendering and metrics (fresh for each frame)
  double chunk_s = 0.5;         // recording transaction length: at most this is lost in a crash
  // Called on the session thread after each tick; null in the product. Tests throttle a session
  // with it to see it fall behind real time and recover.
  std::function<void()> after_tick;
  // A link report of a stale model pauses the session only this long after it (re)started: one
  // sent before (the agent reports once a second) may still speak of the pause's stale model.
  std::chrono::milliseconds stale_model_grace{2000};
};

enum class LiveState { running, paused, finished };
const char* to_string(LiveState state);

// Why a session must pause, from the agent's link report (protocol.h LinkReport): a device whose
// force is off because its model answers a state older than the agent's safety limit (fault
// "stale model", devices/agent kModelMaxAge), so the trainee is cutting without feel. "" when
// no device says so, or the report is not of that shape.
std::string stale_model_reason(const nlohmann::json& report);

class LiveSession : public StreamSource {
 public:
  // How the session reaches its station's agent; called from the session thread.
  struct AgentLink {
    std::function<void(const devices::ForceModel&)> send_force_model;
    // "running", "paused" or "idle" (the session ended), whenever that changes.
    std::function<void(const char* state)> send_notice;
  };

  // Builds the engine (throws std::invalid_argument without a scene or for a bad tick). Does not
  // start: call start().
  LiveSession(LiveSessionParams params, AgentLink agent);
  ~LiveSession() override;  // stops (as "server shutting down") if still running

  void start();
  // Return "" or why the transition is refused (the REST layer's 409).
  std::string pause(const std::string& reason);
  std::string resume();
  // Ends the session and waits until its recording and score are stored. Idempotent.
  void stop(const std::string& reason);

  // From the agent link (any thread). A state from a device the task has no tool for (index >=
  // hands) is counted and ignored.
  void on_device_state(const devices::DeviceState& state, std::uint64_t timestamp_us);
  // The agent's latest link report (protocol.h LinkReport, plus the server's own "loss_up"),
  // shown as "link" in status(). A running session pauses when it says the station renders
  // from a stale model (stale_model_reason), unless it (re)started under stale_model_grace ago.
  void set_link_report(nlohmann::json report);
  void set_agent_online(bool online);

  std::int64_t session_id() const { return params_.session_id; }
  std::int64_t station_id() const { return params_.station_id; }
  std::int64_t recording_id() const { return params_.recording_id; }
  LiveState state() const;
  std::string reason() const;
  bool agent_online() const { return agent_online_.load(); }
  double sim_time_s() const;
  FrameStreamer& streamer() { return *streamer_; }

  std::shared_ptr<const Snapshot> snapshot() const override { return snapshot_.latest(); }
  nlohmann::json status() const override;

 private:
  void run();
  void publish_snapshot();
  void restart_pace();

  LiveSessionParams params_;
  AgentLink agent_;
  SimEngine engine_;
  SnapshotSlot snapshot_;

  mutable std::mutex mutex_;
  // When the session last started or resumed (LiveSessionParams::stale_model_grace).
  std::chrono::steady_clock::time_point running_since_ = std::chrono::steady_clock::now();
  std::condition_variable wake_;
  LiveState state_ = LiveState::running;
  std::string reason_;
  bool stop_requested_ = false;
  // The latest state of each hand's device.
  struct Input {
    devices::DeviceState state;
    bool received = false;
    std::uint64_t timestamp_us = 0;
  };
  std::array<Input, SimEngine::kMaxHands> inputs_;
  nlohmann::json link_report_;
  std::atomic<std::int64_t> ignored_states_{0};
  std::atomic<bool> agent_online_{true};
  std::atomic<double> sim_time_s_{0};
  std::atomic<double> sim_rate_hz_{0};
  std::atomic<std::int64_t> late_ticks_{0};
  std::atomic<std::int64_t> force_models_sent_{0};
  // Keeping up with real time (pace_monitor.h): the session thread reports, status() reads.
  const ShedPlan shed_plan_;
  mutable std::mutex pace_mutex_;
  PaceMonitor pace_;

  std::unique_ptr<FrameStreamer> streamer_;
  std::mutex join_mutex_;  // stop() may race with itself (REST stop, shutdown)
  std::thread thread_;
};

// The number of hands a task needs: its tools[i] is held by device i (1 or 2).
int hands_for(const curriculum::Task& task);

}  // namespace incise::server::live
