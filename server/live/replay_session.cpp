#include "server/live/replay_session.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

#include "server/live/live_session.h"

namespace incise::server::live {
namespace {

using Clock = std::chrono::steady_clock;

// A two-handed recording has a second hand's record in its ticks.
int hands_of(const std::vector<TickRecord>& ticks) {
  return !ticks.empty() && ticks.front().has_second ? 2 : 1;
}

// Longest stretch of simulation one pass of the loop runs before it looks at its controls again.
constexpr std::int64_t kMaxTicksPerPass = 100;
constexpr auto kSnapshotPeriod = std::chrono::milliseconds(16);
// How often a long seek looks whether it should give way (about 30 ms of simulation).
constexpr std::int64_t kAbortCheckTicks = 64;

}  // namespace

void replay_tick(SimEngine& engine, const TickRecord& record) {
  engine.set_shed_level(record.shed);  // as the session shed its physics at this tick
  if (engine.hands() == 1) return engine.tick(record.input);
  const std::array<devices::DeviceState, 2> inputs = {record.input, record.second.input};
  engine.tick(inputs);
}

ReplaySession::ReplaySession(const SessionScene& scene, double tick_s,
                             std::vector<TickRecord> ticks, std::vector<render::MarkView> zones)
    : engine_(scene, tick_s, hands_of(ticks)),
      camera_(camera_for(scene)),
      outside_(outside_camera_for(scene)),
      scene_(scene.shared_setup()),
      zones_(std::move(zones)),
      tick_s_(tick_s),
      ticks_(std::move(ticks)),
      ahead_(scene, tick_s, hands_of(ticks_)) {
  // At most kMaxCheckpoints, in whole multiples of kCheckpointTicks.
  const auto total = static_cast<std::int64_t>(ticks_.size());
  checkpoint_ticks_ = kCheckpointTicks *
                      std::max<std::int64_t>(
                          1, (total / kMaxCheckpoints + kCheckpointTicks - 1) / kCheckpointTicks);
  // The first recorded input places the tool before anything is drawn.
  checkpoints_.emplace(0, engine_.checkpoint());
  publish_snapshot();
}

ReplaySession::~ReplaySession() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  abort_.store(true);
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  if (checkpointer_.joinable()) checkpointer_.join();
  streamer_.reset();
}

void ReplaySession::start() {
  streamer_ = std::make_unique<FrameStreamer>(*this, camera_, outside_, scene_, zones_);
  thread_ = std::thread([this] { run(); });
  checkpointer_ = std::thread([this] { run_ahead(); });
}

void ReplaySession::run_ahead() {
  const auto total = static_cast<std::int64_t>(ticks_.size());
  while (ahead_.ticks() < total) {
    {
      std::lock_guard lock(mutex_);
      if (stop_) return;
    }
    replay_tick(ahead_, ticks_[static_cast<std::size_t>(ahead_.ticks())]);
    if (ahead_.ticks() % checkpoint_ticks_ == 0) {
      SimEngine::Checkpoint c = ahead_.checkpoint();
      std::lock_guard lock(checkpoints_mutex_);
      checkpoints_.try_emplace(ahead_.ticks(), std::move(c));
    }
    checkpointed_to_.store(ahead_.ticks());
  }
}

void ReplaySession::play() {
  std::lock_guard lock(mutex_);
  playing_ = true;
  control_changed_ = true;
  wake_.notify_all();
}

void ReplaySession::pause() {
  std::lock_guard lock(mutex_);
  playing_ = false;
  control_changed_ = true;
  wake_.notify_all();
}

void ReplaySession::set_speed(double speed) {
  std::lock_guard lock(mutex_);
  speed_ = std::clamp(std::isfinite(speed) ? speed : 1.0, kMinSpeed, kMaxSpeed);
  control_changed_ = true;
  wake_.notify_all();
}

void ReplaySession::seek(double t_s) {
  std::lock_guard lock(mutex_);
  seek_to_ = std::clamp(std::isfinite(t_s) ? t_s : 0.0, 0.0, duration_s());
  seeking_ = true;
  seek_target_s_ = seek_to_;
  control_changed_ = true;
  abort_.store(true);  // a seek still running gives way to this one
  wake_.notify_all();
}

nlohmann::json ReplaySession::status() const {
  std::lock_guard lock(mutex_);
  const bool ended = position_s_ >= duration_s() && !end_hash_.empty();
  nlohmann::json out = {{"state", ended ? "ended" : (playing_ ? "playing" : "paused")},
                        {"reason", ""},
                        {"agent_online", false},
                        {"duration_s", duration_s()},
                        {"speed", speed_},
                        {"playing", playing_},
                        {"position_s", position_s_},
                        {"seeking", seeking_},
                        {"hands", engine_.hands()},
                        {"frame_latency_ms", frame_latency().median()}};
  if (ended) out["state_hash"] = end_hash_;
  if (seeking_) out["seek_to_s"] = seek_target_s_;
  if (streamer_) {
    const auto error = streamer_->error();
    if (!error.empty()) out["render_error"] = error;
  }
  return out;
}

void ReplaySession::publish_snapshot() {
  snapshot_.publish(make_snapshot(engine_));
  if (streamer_) streamer_->poke();
}

bool ReplaySession::advance_to(std::int64_t target) {
  target = std::clamp<std::int64_t>(target, 0, static_cast<std::int64_t>(ticks_.size()));
  {
    // Back to the nearest checkpoint at or before the target, or forward over whole intervals
    // already computed (the checkpoint at tick 0 always exists).
    std::lock_guard lock(checkpoints_mutex_);
    auto it = checkpoints_.upper_bound(target);
    --it;
    if (target < engine_.ticks() || it->first > engine_.ticks()) engine_.restore(it->second);
  }
  while (engine_.ticks() < target) {
    replay_tick(engine_, ticks_[static_cast<std::size_t>(engine_.ticks())]);
    if (engine_.ticks() % checkpoint_ticks_ == 0 && engine_.ticks() > checkpointed_to_.load()) {
      SimEngine::Checkpoint c = engine_.checkpoint();
      std::lock_guard lock(checkpoints_mutex_);
      checkpoints_.try_emplace(engine_.ticks(), std::move(c));
    }
    if (engine_.ticks() % kAbortCheckTicks == 0 && abort_.load()) return false;
  }
  return true;
}

void ReplaySession::run() {
  const auto total = static_cast<std::int64_t>(ticks_.size());
  // Pacing: the tick that should be reached is origin_tick + (now - origin) * speed / tick_s.
  auto origin = Clock::now();
  std::int64_t origin_tick = 0;
  auto last_snapshot = Clock::now();
  while (true) {
    bool playing;
    double speed;
    double seek_to;
    {
      std::unique_lock lock(mutex_);
      if (!playing_ && seek_to_ < 0) {
        wake_.wait(lock, [this] { return stop_ || playing_ || seek_to_ >= 0; });
      }
      if (stop_) return;
      playing = playing_;
      speed = speed_;
      seek_to = seek_to_;
      seek_to_ = -1;
      if (seek_to >= 0) abort_.store(false);  // under the lock: a later seek raises it again
      if (control_changed_) {
        control_changed_ = false;
        origin = Clock::now();
        origin_tick = engine_.ticks();
      }
    }
    if (seek_to >= 0) {
      if (!advance_to(std::llround(seek_to / tick_s_))) continue;  // superseded or closing
      publish_snapshot();
      {
        std::lock_guard lock(mutex_);
        position_s_ = engine_.time_s();
        if (seek_to_ < 0) seeking_ = false;  // landed, and no newer seek waits
      }
      last_snapshot = Clock::now();
      origin = Clock::now();
      origin_tick = engine_.ticks();
    }
    if (playing) {
      const double elapsed = std::chrono::duration<double>(Clock::now() - origin).count();
      const auto due = std::min(
          total, origin_tick + static_cast<std::int64_t>(std::floor(elapsed * speed / tick_s_)));
      advance_to(std::min(due, engine_.ticks() + kMaxTicksPerPass));
      if (Clock::now() - last_snapshot >= kSnapshotPeriod || engine_.ticks() == total) {
        publish_snapshot();
        last_snapshot = Clock::now();
      }
      if (engine_.ticks() == total) {
        const auto hash = engine_.state_hash();
        std::lock_guard lock(mutex_);
        end_hash_ = hash;
        playing_ = false;
      } else if (due <= engine_.ticks()) {
        std::unique_lock lock(mutex_);
        wake_.wait_for(lock, std::chrono::milliseconds(2),
                       [this] { return stop_ || control_changed_ || seek_to_ >= 0; });
      }
    }
    {
      std::lock_guard lock(mutex_);
      position_s_ = engine_.time_s();
      if (engine_.ticks() == total && end_hash_.empty()) end_hash_ = engine_.state_hash();
    }
  }
}

std::string ReplaySession::final_state_hash(const SessionScene& scene, double tick_s,
                                            const std::vector<TickRecord>& ticks) {
  SimEngine engine(scene, tick_s, hands_of(ticks));
  for (const auto& r : ticks)
    replay_tick(engine, r);
  return engine.state_hash();
}

}  // namespace incise::server::live
