#pragma once
// The 1 kHz haptic loop, for one or two devices (a station's two hands). Each tick, per device:
// poll it, evaluate the latest force model for it at the tool tip, pass the force through the
// ForceGuard (virtual coupling, watchdog fade, passivity guard, limits; docs/haptic_safety.md),
// command it, and every send_every-th tick hand the state to the io thread unless the deadband
// holds it back (the hand has not moved). The loop never waits for the network: models and
// states pass through the lock-free HapticChannel.
//
// The watchdog fades the force to zero within ForceFade::kSteps ticks of any fault: link down,
// no model for kModelMaxGap, a model answering a state over kModelMaxAge old, a driver fault, a
// non-finite or impossibly fast device state, a starved loop, or stop().
//
// tick() does no allocation, locking or I/O. start() runs it on a thread of its own at absolute
// steady-clock deadlines (start + n ms), so handler latency does not accumulate into drift.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <span>
#include <thread>

#include "devices/agent/force_fade.h"
#include "devices/agent/force_guard.h"
#include "devices/agent/force_model_evaluator.h"
#include "devices/agent/haptic_channel.h"
#include "devices/agent/loop_stats.h"
#include "devices/device.h"
#include "devices/workspace_mapping.h"

namespace incise::devices::agent {

inline constexpr Clock::duration kTickPeriod = std::chrono::milliseconds(1);
// A tick this long after the previous one means the loop was starved: the watchdog fades.
inline constexpr Clock::duration kMaxTickGap = std::chrono::milliseconds(5);

// Device-state messages are held back while the hand is still: a state is sent when it differs
// from the last one sent by more than these, or keepalive after it. The server holds the last
// state, so what it simulates and records stays within the deadband of the hand.
struct Deadband {
  bool enabled = true;
  double position_m = 5e-5;  // 0.05 mm: below what a hand holds still
  double angle_rad = 1e-3;   // 0.06 degrees
  double jaw = 2e-3;
  Clock::duration keepalive = std::chrono::milliseconds(50);

  // Whether a state must be sent given the last one sent.
  bool moved(const DeviceState& state, const DeviceState& last_sent) const;
};

struct LoopSettings {
  int send_every = 2;  // queue a state every k-th tick (500 Hz at k = 2)
  Deadband deadband;
  ForceGuardSettings guard;
};

class HapticLoop {
 public:
  // The devices (1 or kMaxDevices; device i reports as device_index i) and channel must outlive
  // the loop. epoch is t = 0 of device polls and state timestamps.
  HapticLoop(std::span<Device* const> devices, HapticChannel& channel, const LoopSettings& settings,
             Clock::time_point epoch);
  // One device, the deadband off and the guard transparent: the model exactly (plumbing tests).
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
  const Vec3& last_force(std::size_t device = 0) const { return hands_[device].last_force; }
  double fade_factor(std::size_t device = 0) const { return hands_[device].fade.factor(); }
  GuardFault fault(std::size_t device = 0) const { return hands_[device].fault; }
  const ForceGuard& guard(std::size_t device = 0) const { return hands_[device].guard; }
  const DeviceState& last_state(std::size_t device = 0) const { return hands_[device].state; }
  std::size_t device_count() const { return count_; }
  uint64_t ticks() const { return ticks_; }

 private:
  // Everything the loop keeps per device.
  struct Hand {
    Device* device = nullptr;
    ForceModelEvaluator evaluator;
    ForceGuard guard;
    ForceFade fade;
    uint64_t model_version = 0;  // of the model in evaluator
    ReceivedModel model;         // the latest, in the scene frame as the server sent it
    WorkspaceMapping mapping;    // device -> scene (identity until the station's calibration)
    uint64_t mapping_version = 0;
    DeviceState state;  // the device's, in its own frame
    GuardFault fault = GuardFault::NoModel;
    Vec3 last_force;
    DeviceState last_sent;
    Clock::time_point last_sent_at;
    bool sent_any = false;
  };

  void tick_hand(Hand& hand, std::size_t index, Clock::time_point now, double dt, bool late,
                 bool send_tick, uint64_t t_us);
  void run();
  bool all_silent() const {
    for (std::size_t i = 0; i < count_; ++i)
      if (hands_[i].fade.factor() > 0.0) return false;
    return true;
  }

  std::array<Hand, kMaxDevices> hands_;
  std::size_t count_ = 0;
  HapticChannel& channel_;
  const uint64_t send_every_;
  const Deadband deadband_;
  const Clock::time_point epoch_;
  LoopStats stats_;
  uint64_t ticks_ = 0;
  Clock::time_point previous_tick_;

  std::atomic<bool> stopping_{false};
  std::thread thread_;
};

}  // namespace incise::devices::agent
