#include "devices/agent/haptic_loop.h"

#include <algorithm>

#if defined(__linux__)
#include <pthread.h>
#include <sys/prctl.h>
#endif

namespace incise::devices::agent {
namespace {

void prepare_thread() {
#if defined(__linux__)
  // Linux may delay a timer expiry by the thread's slack (50 us by default) to batch wake-ups;
  // at 1 kHz that is 5 % jitter for nothing.
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  pthread_setname_np(pthread_self(), "incise-haptic");
#endif
}

}  // namespace

HapticLoop::HapticLoop(Device& device, HapticChannel& channel, int send_every,
                       Clock::time_point epoch)
    : device_(device),
      channel_(channel),
      send_every_(static_cast<uint64_t>(std::max(send_every, 1))),
      epoch_(epoch),
      stats_(kTickPeriod) {}

void HapticLoop::tick(Clock::time_point now) {
  const Clock::duration since_epoch = now - epoch_;
  const DeviceState state = device_.poll(std::chrono::duration<double>(since_epoch).count());

  if (channel_.model.version() != model_version_) {
    const ReceivedModel received = channel_.model.read(model_version_);
    evaluator_.set_model(received.model, received.received_at);
  }
  const bool link_up = channel_.link_up.load(std::memory_order_acquire);
  const bool render = link_up && !stopping_.load(std::memory_order_relaxed) &&
                      evaluator_.fresh(now) &&
                      evaluator_.model().device_index == state.device_index;
  const double factor = fade_.step(render);
  Vec3 force;
  if (factor > 0.0) {
    const Vec3 full = evaluator_.force_at(state.position);
    force = {factor * full.x, factor * full.y, factor * full.z};
  }
  device_.set_force(force);
  last_force_ = force;

  if (link_up && ticks_ % send_every_ == 0) {
    const auto t_us = std::chrono::duration_cast<std::chrono::microseconds>(since_epoch).count();
    channel_.states.push({state, static_cast<uint64_t>(std::max<int64_t>(t_us, 0))});
  }
  ++ticks_;
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
    if (stopping_.load(std::memory_order_relaxed) && fade_.factor() == 0.0) break;

    deadline += kTickPeriod;
    const Clock::time_point done = Clock::now();
    if (done >= deadline) {
      stats_.record_overrun();
      // A whole period or more behind (the thread was descheduled): skip the missed ticks and
      // rejoin the grid rather than run them back to back.
      deadline += ((done - deadline) / kTickPeriod) * kTickPeriod;
    }
  }
  device_.set_force({});
  last_force_ = {};
}

}  // namespace incise::devices::agent
