#pragma once
// The 1 kHz haptic loop. Each tick: poll the device, evaluate the latest force model at the tool
// tip, scale it by the fade factor (ForceFade: on while the link is up and the model is at most
// kModelMaxAge old), command the force, and every send_every-th tick hand the state to the io
// thread. The loop never waits for the network: models and states pass through the lock-free
// HapticChannel.
//
// tick() does no allocation, locking or I/O. start() runs it on a thread of its own at absolute
// steady-clock deadlines (start + n ms), so handler latency does not accumulate into drift.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <thread>

#include "devices/agent/force_fade.h"
#include "devices/agent/force_model_evaluator.h"
#include "devices/agent/haptic_channel.h"
#include "devices/agent/loop_stats.h"
#include "devices/device.h"

namespace incise::devices::agent {

inline constexpr Clock::duration kTickPeriod = std::chrono::milliseconds(1);

class HapticLoop {
 public:
  // device and channel must outlive the loop. send_every >= 1; epoch is t = 0 of device polls
  // and state timestamps.
  HapticLoop(Device& device, HapticChannel& channel, int send_every, Clock::time_point epoch);
  ~HapticLoop() { stop(); }

  HapticLoop(const HapticLoop&) = delete;
  HapticLoop& operator=(const HapticLoop&) = delete;

  // One tick at now (non-decreasing from call to call). Called by the loop thread; tests call it
  // directly instead of start().
  void tick(Clock::time_point now);

  // Starts the loop thread.
  void start();
  // Fades the force out (at most ForceFade::kSteps more ticks), commands zero force and joins
  // the thread. Idempotent; also done by the destructor.
  void stop();

  // Any thread.
  LoopSummary summary() const { return stats_.summary(); }

  // The thread that calls tick(), or any thread once stopped.
  const Vec3& last_force() const { return last_force_; }
  double fade_factor() const { return fade_.factor(); }
  uint64_t ticks() const { return ticks_; }

 private:
  void run();

  Device& device_;
  HapticChannel& channel_;
  const uint64_t send_every_;
  const Clock::time_point epoch_;

  ForceModelEvaluator evaluator_;
  ForceFade fade_;
  LoopStats stats_;
  uint64_t model_version_ = 0;  // of the model in evaluator_
  uint64_t ticks_ = 0;
  Vec3 last_force_;

  std::atomic<bool> stopping_{false};
  std::thread thread_;
};

}  // namespace incise::devices::agent
