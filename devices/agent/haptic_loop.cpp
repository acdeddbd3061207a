#include "devices/agent/haptic_loop.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>

#if defined(__linux__)
#include <pthread.h>
#include <sys/prctl.h>
#endif

namespace incise::devices::agent {
namespace {

void bump(std::atomic<uint64_t>& counter) {
  counter.store(counter.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
}

void prepare_thread() {
#if defined(__linux__)
  // Linux may delay a timer expiry by the thread's slack (50 us by default) to batch wake-ups;
  // at 1 kHz that is 5 % jitter for nothing.
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  pthread_setname_np(pthread_self(), "incise-haptic");
#endif
}

}  // namespace

bool Deadband::moved(const DeviceState& state, const DeviceState& last_sent) const {
  if (state.buttons != last_sent.buttons) return true;
  if (std::abs(state.jaw - last_sent.jaw) > jaw) return true;
  const double dx = state.position.x - last_sent.position.x;
  const double dy = state.position.y - last_sent.position.y;
  const double dz = state.position.z - last_sent.position.z;
  if (dx * dx + dy * dy + dz * dz > position_m * position_m) return true;
  // The angle between two unit quaternions is 2 acos(|<q1, q2>|).
  const Quat& a = state.orientation;
  const Quat& b = last_sent.orientation;
  const double cosine = std::min(1.0, std::abs(a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z));
  return 2.0 * std::acos(cosine) > angle_rad;
}

HapticLoop::HapticLoop(std::span<Device* const> devices, HapticChannel& channel,
                       const LoopSettings& settings, Clock::time_point epoch)
    : count_(std::min(devices.size(), kMaxDevices)),
      channel_(channel),
      send_every_(static_cast<uint64_t>(std::max(settings.send_every, 1))),
      deadband_(settings.deadband),
      epoch_(epoch),
      stats_(kTickPeriod) {
  for (std::size_t i = 0; i < count_; ++i) {
    hands_[i].device = devices[i];
    hands_[i].guard = ForceGuard(settings.guard);
  }
}

namespace {
LoopSettings plumbing_settings(int send_every) {
  LoopSettings settings;
  settings.send_every = send_every;
  settings.deadband.enabled = false;
  settings.guard = ForceGuardSettings::transparent();
  return settings;
}
}  // namespace

HapticLoop::HapticLoop(Device& device, HapticChannel& channel, int send_every,
                       Clock::time_point epoch)
    : HapticLoop(std::span<Device* const>(std::array<Device*, 1>{&device}), channel,
                 plumbing_settings(send_every), epoch) {}

void HapticLoop::tick(Clock::time_point now) {
  const Clock::duration since_epoch = now - epoch_;
  const auto t_us = static_cast<uint64_t>(std::max<int64_t>(
      std::chrono::duration_cast<std::chrono::microseconds>(since_epoch).count(), 0));
  const bool first = ticks_ == 0;
  const double dt = first ? 0.0 : std::chrono::duration<double>(now - previous_tick_).count();
  const bool late = !first && now - previous_tick_ > kMaxTickGap;
  previous_tick_ = now;
  const bool send_tick = ticks_ % send_every_ == 0;
  for (std::size_t i = 0; i < count_; ++i)
    tick_hand(hands_[i], i, now, dt, late, send_tick, t_us);
  ++ticks_;
  channel_.loop_ticks.store(ticks_, std::memory_order_relaxed);
}

void HapticLoop::tick_hand(Hand& hand, std::size_t index, Clock::time_point now, double dt,
                           bool late, bool send_tick, uint64_t t_us) {
  DeviceState state = hand.device->poll(std::chrono::duration<double>(now - epoch_).count());
  state.device_index = static_cast<uint8_t>(index);
  // Everything here runs in the device's frame: the server's model is mapped into it (virtual
  // work kept), and only the state sent to the server is mapped to the scene.
  // A new mapping drops the model in hand: it answered a state mapped the old way. The next
  // model renders (the watchdog fades out and back in meanwhile).
  Seqlock<WorkspaceMapping>& mapping_slot = channel_.mappings[index];
  if (mapping_slot.version() != hand.mapping_version) {
    hand.mapping = mapping_slot.read(hand.mapping_version);
    hand.evaluator.clear();
  }
  Seqlock<ReceivedModel>& slot = channel_.models[index];
  if (slot.version() != hand.model_version) {
    hand.model = slot.read(hand.model_version);
    hand.evaluator.set_model(hand.mapping.force_model_to_device(hand.model.model),
                             hand.model.received_at);
  }
  const Vec3& x = state.position;
  const bool finite = std::isfinite(x.x) && std::isfinite(x.y) && std::isfinite(x.z);
  const Vec3 velocity = finite ? hand.guard.track(x, dt) : hand.guard.velocity();
  const double speed =
      std::sqrt(velocity.x * velocity.x + velocity.y * velocity.y + velocity.z * velocity.z);
  // How old the model's picture of the world is: the link's round trip plus the time since the
  // model arrived. (The state it echoes can be older without the model being stale: while the
  // deadband holds the hand's state, the server keeps answering the last one sent.) Before the
  // link has measured a round trip, the echo tells.
  const uint64_t round_trip_us =
      channel_.telemetry[index].round_trip_us.load(std::memory_order_relaxed);
  const uint64_t age_us =
      round_trip_us == 0
          ? hand.evaluator.age_us(t_us)
          : round_trip_us + static_cast<uint64_t>(std::max<int64_t>(
                                0, std::chrono::duration_cast<std::chrono::microseconds>(
                                       now - hand.evaluator.received_at())
                                       .count()));

  GuardFault fault = GuardFault::None;
  if (stopping_.load(std::memory_order_relaxed))
    fault = GuardFault::Stopping;
  else if (!channel_.link_up.load(std::memory_order_acquire))
    fault = GuardFault::LinkDown;
  else if (!hand.device->fault().empty())
    fault = GuardFault::DeviceFault;
  else if (!finite || speed > hand.guard.settings().max_speed_m_s)
    fault = GuardFault::BadState;
  else if (late)
    fault = GuardFault::LateTick;
  else if (!hand.evaluator.fresh(now) || hand.evaluator.model().device_index != index)
    fault = GuardFault::NoModel;
  else if (age_us >
           static_cast<uint64_t>(
               std::chrono::duration_cast<std::chrono::microseconds>(kModelMaxAge).count()))
    fault = GuardFault::StaleModel;
  hand.fault = fault;

  const double factor = hand.fade.step(fault == GuardFault::None);
  // Once the force is off, what the guard remembers (velocity, energy credit or debt, the slew's
  // last force) belongs to before the fault: the hand may have moved, the link changed. Start
  // afresh, tracking from this tick's position.
  if (factor == 0.0 && fault != GuardFault::None) {
    hand.guard.reset();
    if (finite) hand.guard.track(x, dt);
  }
  Vec3 desired;
  if (factor > 0.0 && finite) {
    const Vec3 coupled =
        hand.guard.couple(hand.evaluator.force_at(x), hand.evaluator.model().stiffness,
                          static_cast<double>(age_us) * 1e-6);
    desired = {factor * coupled.x, factor * coupled.y, factor * coupled.z};
  }
  const Vec3 force = hand.guard.finish(desired, dt, factor == 0.0 || !finite);
  hand.device->set_force(force);
  hand.last_force = force;
  hand.state = state;

  DeviceTelemetry& telemetry = channel_.telemetry[index];
  telemetry.model_age_us.store(static_cast<uint32_t>(std::min<uint64_t>(age_us, UINT32_MAX)),
                               std::memory_order_relaxed);
  telemetry.fault.store(static_cast<uint8_t>(fault), std::memory_order_relaxed);
  telemetry.force_n.store(
      static_cast<float>(std::sqrt(force.x * force.x + force.y * force.y + force.z * force.z)),
      std::memory_order_relaxed);
  telemetry.damping.store(static_cast<float>(hand.guard.last_damping()), std::memory_order_relaxed);
  telemetry.dissipated_j.store(static_cast<float>(hand.guard.dissipated_j()),
                               std::memory_order_relaxed);
  if (fault != GuardFault::None) bump(telemetry.fault_ticks);

  if (!send_tick || !finite || !channel_.link_up.load(std::memory_order_acquire)) return;
  const bool send = !deadband_.enabled || !hand.sent_any ||
                    now - hand.last_sent_at >= deadband_.keepalive ||
                    deadband_.moved(state, hand.last_sent);
  if (send) {
    hand.last_sent = state;
    hand.last_sent_at = now;
    hand.sent_any = true;
    bump(telemetry.states_queued);
  } else {
    bump(telemetry.states_held);
  }
  channel_.states.push({hand.mapping.state_to_scene(state), t_us, send});
}

void HapticLoop::start() {
  if (thread_.joinable()) return;
  stopping_.store(false);
  thread_ = std::thread([this] { run(); });
}

void HapticLoop::stop() {
  stopping_.store(true);
  if (thread_.joinable()) thread_.join();
}

void HapticLoop::run() {
  prepare_thread();
  Clock::time_point deadline = Clock::now();
  Clock::time_point previous;
  bool first = true;
  for (;;) {
    std::this_thread::sleep_until(deadline);
    const Clock::time_point now = Clock::now();
    if (!first) stats_.record_period(now - previous);
    first = false;
    previous = now;

    tick(now);
    if (stopping_.load(std::memory_order_relaxed) && all_silent()) break;

    deadline += kTickPeriod;
    const Clock::time_point done = Clock::now();
    if (done >= deadline) {
      stats_.record_overrun();
      // A whole period or more behind (the thread was descheduled): skip the missed ticks and
      // rejoin the grid rather than run them back to back.
      deadline += ((done - deadline) / kTickPeriod) * kTickPeriod;
    }
  }
  for (std::size_t i = 0; i < count_; ++i) {
    hands_[i].device->set_force({});
    hands_[i].last_force = {};
  }
}

}  // namespace incise::devices::agent
