#pragma once
// A replay (docs/architecture.md, "A live session, end to end"): a session whose device is the
// recording. The same SimEngine re-runs the recorded ticks, so the replay reproduces the run bit
// for bit, paced at `speed` times real time. Checkpoints of the engine (whole scenes, surgical ones
// included) make seeking fast both ways: a seek restores the nearest checkpoint at or before the
// target and runs forward from there without pacing. A second engine on its own thread runs the
// recording ahead from the start, unpaced, leaving a checkpoint every checkpoint_ticks(), so a
// seek forward past where the replay has played lands as fast as one backwards once it has passed.
// The interval is kCheckpointTicks, longer for recordings over kMaxCheckpoints of them (memory).
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "server/live/frame_streamer.h"
#include "server/live/sim_engine.h"
#include "server/live/snapshot.h"
#include "server/live/tick_record.h"

namespace incise::server::live {

// Runs one recorded tick on engine: both hands if the engine has two.
void replay_tick(SimEngine& engine, const TickRecord& record);

class ReplaySession : public StreamSource {
 public:
  static constexpr std::int64_t kCheckpointTicks = 250;  // 0.5 s at 500 Hz
  static constexpr std::int64_t kMaxCheckpoints = 400;
  static constexpr double kMinSpeed = 0.25;
  static constexpr double kMaxSpeed = 4.0;

  // zones: drawn in the picture (the recorded task's visible zones, task_zones). Throws like
  // SimEngine for a bad scene.
  ReplaySession(const SessionScene& scene, double tick_s, std::vector<TickRecord> ticks,
                std::vector<render::MarkView> zones = {});
  ~ReplaySession() override;

  // Starts the replay thread and its pictures (on the render pool). The replay opens paused at t =
  // 0, showing its first picture, at 1x: the viewer chooses when it plays.
  void start();
  void play();
  void pause();
  void set_speed(double speed);  // clamped to [kMinSpeed, kMaxSpeed]
  void seek(double t_s);         // clamped to [0, duration]

  double duration_s() const { return static_cast<double>(ticks_.size()) * tick_s_; }
  std::int64_t checkpoint_ticks() const { return checkpoint_ticks_; }
  // The tick up to which the engine running ahead has left its checkpoints.
  std::int64_t checkpointed_to() const { return checkpointed_to_.load(); }
  FrameStreamer& streamer() { return *streamer_; }

  std::shared_ptr<const Snapshot> snapshot() const override { return snapshot_.latest(); }
  nlohmann::json status() const override;

  // Runs the whole recording without pacing and returns SimEngine::state_hash() at the end.
  static std::string final_state_hash(const SessionScene& scene, double tick_s,
                                      const std::vector<TickRecord>& ticks);

 private:
  void run();
  // Runs the engine to target_tick (engine thread only). Returns false if it gave up early because
  // abort_ was raised (a newer seek, or the replay closing): a long seek stays interruptible.
  bool advance_to(std::int64_t target_tick);
  // The checkpointer thread: ahead_ through the whole recording.
  void run_ahead();
  void publish_snapshot();

  SimEngine engine_;
  render::Camera camera_;
  render::Camera outside_;
  std::shared_ptr<const sim::surgery::SurgicalSceneSetup> scene_;  // for the picture
  std::vector<render::MarkView> zones_;
  double tick_s_;
  std::vector<TickRecord> ticks_;
  std::int64_t checkpoint_ticks_ = kCheckpointTicks;
  std::map<std::int64_t, SimEngine::Checkpoint> checkpoints_;  // guarded by checkpoints_mutex_
  mutable std::mutex checkpoints_mutex_;
  SimEngine ahead_;  // the checkpointer thread's
  std::atomic<std::int64_t> checkpointed_to_{0};
  SnapshotSlot snapshot_;

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  bool playing_ = false;
  // A seek asked for and not landed yet (its target [s]), so that the viewer sees it working.
  bool seeking_ = false;
  double seek_target_s_ = 0;
  double speed_ = 1.0;
  double seek_to_ = -1;  // >= 0: a pending seek [s]
  bool control_changed_ = false;
  std::atomic<bool> abort_{false};
  double position_s_ = 0;
  std::string end_hash_;  // set when the replay reaches the end

  std::unique_ptr<FrameStreamer> streamer_;
  std::thread thread_;
  std::thread checkpointer_;
};

}  // namespace incise::server::live
