// The deadband on device-state messages (Deadband in devices/agent/haptic_loop.h): the pure
// moved() test at its thresholds, and the haptic loop's use of it, driven with synthetic times:
// what is queued, what is held (TimedState::send = false) and that the server's sample and hold
// of the sent states stays within the deadband of the hand.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <random>
#include <vector>

#include "devices/agent/haptic_loop.h"

namespace incise::devices::agent {
namespace {

using namespace std::chrono_literals;

// Reports whatever state the test sets: pose, jaw and buttons.
class ScriptedDevice final : public Device {
 public:
  std::string_view name() const override { return "scripted"; }
  int degrees_of_freedom() const override { return 7; }
  DeviceCapabilities capabilities() const override { return {.has_jaw = true, .button_count = 2}; }
  DeviceState poll(double) override { return state; }

  DeviceState state;
};

// A rotation by angle [rad] about a unit axis, as a quaternion.
Quat rotation(double angle, double ax, double ay, double az) {
  const double s = std::sin(angle / 2);
  return {std::cos(angle / 2), s * ax, s * ay, s * az};
}

Quat multiply(const Quat& a, const Quat& b) {
  return {
      a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
      a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

DeviceState resting_state() {
  DeviceState s;
  s.position = {0.04, 0.04, 0.03};
  s.orientation = rotation(0.3, 0.0, 0.6, 0.8);
  s.jaw = 0.25f;
  return s;
}

TEST(DeadbandMoved, EachChannelTriggersJustAboveItsThreshold) {
  const Deadband band;
  const DeviceState sent = resting_state();
  EXPECT_FALSE(band.moved(sent, sent));

  DeviceState s = sent;
  s.position.x += 0.9 * band.position_m;
  EXPECT_FALSE(band.moved(s, sent));
  s.position.x = sent.position.x + 1.1 * band.position_m;
  EXPECT_TRUE(band.moved(s, sent));
  // The position test is on the distance, not per axis: 0.8 of the band on two axes is 1.13.
  s = sent;
  s.position.y += 0.8 * band.position_m;
  s.position.z -= 0.8 * band.position_m;
  EXPECT_TRUE(band.moved(s, sent));

  // Angle between orientations: 2 acos |<q1, q2>|, about any axis.
  s = sent;
  s.orientation = multiply(rotation(0.8 * band.angle_rad, 1.0, 0.0, 0.0), sent.orientation);
  EXPECT_FALSE(band.moved(s, sent));
  s.orientation = multiply(rotation(1.2 * band.angle_rad, 0.0, 0.0, 1.0), sent.orientation);
  EXPECT_TRUE(band.moved(s, sent));
  // q and -q are the same rotation.
  s.orientation = {-sent.orientation.w, -sent.orientation.x, -sent.orientation.y,
                   -sent.orientation.z};
  EXPECT_FALSE(band.moved(s, sent));

  s = sent;
  s.jaw = sent.jaw + static_cast<float>(0.8 * band.jaw);
  EXPECT_FALSE(band.moved(s, sent));
  s.jaw = sent.jaw - static_cast<float>(1.2 * band.jaw);
  EXPECT_TRUE(band.moved(s, sent));

  // Any button change is sent, however still the hand.
  s = sent;
  s.buttons = 0b10;
  EXPECT_TRUE(band.moved(s, sent));
}

// A loop over one or two scripted devices, ticked by hand once per ms from t0, link up (no
// force model: the watchdog keeps the force off, which does not affect what is sent).
class LoopRig {
 public:
  explicit LoopRig(std::size_t devices, LoopSettings settings = {}) : count_(devices) {
    for (std::size_t i = 0; i < count_; ++i) {
      devices_[i].state = resting_state();
      pointers_[i] = &devices_[i];
    }
    channel_.link_up = true;
    loop_.emplace(std::span<Device* const>(pointers_.data(), count_), channel_, settings, t0_);
  }

  ScriptedDevice& device(std::size_t i) { return devices_[i]; }
  HapticChannel& channel() { return channel_; }

  // Ticks at ms and returns the states it queued.
  std::vector<TimedState> tick(int ms) {
    loop_->tick(t0_ + std::chrono::milliseconds(ms));
    std::vector<TimedState> queued;
    TimedState s;
    while (channel_.states.pop(s))
      queued.push_back(s);
    return queued;
  }

 private:
  const Clock::time_point t0_ = Clock::now();
  std::size_t count_;
  std::array<ScriptedDevice, kMaxDevices> devices_;
  std::array<Device*, kMaxDevices> pointers_{};
  HapticChannel channel_;
  std::optional<HapticLoop> loop_;
};

TEST(DeadbandLoop, AStillHandSendsOnlyKeepalives) {
  const LoopSettings settings;  // send every 2nd tick, keepalive 50 ms
  LoopRig loop(1, settings);
  const auto keepalive_us = static_cast<uint64_t>(
      std::chrono::duration_cast<std::chrono::microseconds>(settings.deadband.keepalive).count());
  int sent = 0, held = 0;
  for (int ms = 0; ms < 1000; ++ms) {
    const std::vector<TimedState> queued = loop.tick(ms);
    ASSERT_EQ(queued.size(), ms % settings.send_every == 0 ? 1u : 0u) << ms;
    for (const TimedState& s : queued) {
      // Sent at 0 (the first state) and then exactly one keepalive period after the last.
      EXPECT_EQ(s.send, s.timestamp_us % keepalive_us == 0) << ms;
      (s.send ? sent : held) += 1;
    }
  }
  EXPECT_EQ(sent, 20);  // 1 s / 50 ms
  EXPECT_EQ(held, 500 - 20);
  EXPECT_EQ(loop.channel().telemetry[0].states_queued.load(), 20u);
  EXPECT_EQ(loop.channel().telemetry[0].states_held.load(), 480u);
}

TEST(DeadbandLoop, AMovingHandSendsEverySendTick) {
  LoopRig loop(1);
  int sent = 0;
  for (int ms = 0; ms < 400; ++ms) {
    loop.device(0).state.position.x += 1e-4;  // 0.1 m/s: 0.2 mm per send tick
    for (const TimedState& s : loop.tick(ms)) {
      EXPECT_TRUE(s.send) << ms;
      ++sent;
    }
  }
  EXPECT_EQ(sent, 200);
  EXPECT_EQ(loop.channel().telemetry[0].states_held.load(), 0u);
}

TEST(DeadbandLoop, WithTheDeadbandOffEveryStateIsSent) {
  LoopSettings settings;
  settings.deadband.enabled = false;
  LoopRig loop(1, settings);
  int sent = 0;
  for (int ms = 0; ms < 400; ++ms)
    for (const TimedState& s : loop.tick(ms))
      sent += s.send ? 1 : 0;
  EXPECT_EQ(sent, 200);
  EXPECT_EQ(loop.channel().telemetry[0].states_held.load(), 0u);
}

// One change from rest, applied at a send tick well inside the keepalive period, and whether
// that tick's state is sent.
bool sent_after(void (*change)(DeviceState&, const Deadband&)) {
  LoopRig loop(1);
  const Deadband band;
  loop.tick(0);  // the first state is always sent
  for (int ms = 1; ms < 20; ++ms) {
    for (const TimedState& s : loop.tick(ms)) {
      if (s.send) ADD_FAILURE() << "a still hand sent at " << ms << " ms";
    }
  }
  change(loop.device(0).state, band);
  const std::vector<TimedState> queued = loop.tick(20);
  EXPECT_EQ(queued.size(), 1u);
  return !queued.empty() && queued.front().send;
}

TEST(DeadbandLoop, SendsAsSoonAsAnyChannelLeavesTheBand) {
  EXPECT_FALSE(
      sent_after([](DeviceState& s, const Deadband& b) { s.position.z += 0.9 * b.position_m; }));
  EXPECT_TRUE(
      sent_after([](DeviceState& s, const Deadband& b) { s.position.z += 1.1 * b.position_m; }));
  EXPECT_FALSE(sent_after([](DeviceState& s, const Deadband& b) {
    s.orientation = multiply(rotation(0.8 * b.angle_rad, 0, 1, 0), s.orientation);
  }));
  EXPECT_TRUE(sent_after([](DeviceState& s, const Deadband& b) {
    s.orientation = multiply(rotation(1.2 * b.angle_rad, 0, 1, 0), s.orientation);
  }));
  EXPECT_FALSE(sent_after(
      [](DeviceState& s, const Deadband& b) { s.jaw += static_cast<float>(0.8 * b.jaw); }));
  EXPECT_TRUE(sent_after(
      [](DeviceState& s, const Deadband& b) { s.jaw += static_cast<float>(1.2 * b.jaw); }));
  EXPECT_TRUE(sent_after([](DeviceState& s, const Deadband&) { s.buttons ^= 1; }));
}

TEST(DeadbandLoop, TheLastSentStateIsWithinTheBandOfEveryHeldOne) {
  // A random walk of a hand that dwells and drifts: what the server holds (the last state sent)
  // must stay within the deadband of the hand, and every state sent between keepalives must be
  // one that left the band.
  LoopRig loop(1);
  const Deadband band;
  std::mt19937 random(11);
  std::normal_distribution<double> step(0.0, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::optional<TimedState> last_sent;
  int sent = 0, held = 0, moved_sends = 0;
  for (int ms = 0; ms < 5000; ++ms) {
    DeviceState& s = loop.device(0).state;
    // Moving for 40 ms in every 100, still (below a tenth of the band) otherwise.
    const double scale = (ms / 40) % 5 < 2 ? 1.0 : 0.02;
    s.position.x += scale * 2e-5 * step(random);
    s.position.y += scale * 2e-5 * step(random);
    s.position.z += scale * 2e-5 * step(random);
    s.orientation =
        multiply(rotation(scale * 4e-4 * std::abs(step(random)), 0.6, 0.0, 0.8), s.orientation);
    s.jaw = std::clamp(s.jaw + static_cast<float>(scale * 8e-4 * step(random)), 0.0f, 1.0f);
    if (unit(random) < 0.002) s.buttons ^= 1;
    for (const TimedState& queued : loop.tick(ms)) {
      if (queued.send) {
        ++sent;
        const bool keepalive = last_sent && queued.timestamp_us - last_sent->timestamp_us >= 50'000;
        if (last_sent && !keepalive) {
          EXPECT_TRUE(band.moved(queued.state, last_sent->state)) << ms;
          ++moved_sends;
        }
        last_sent = queued;
      } else {
        ++held;
        ASSERT_TRUE(last_sent.has_value());
        EXPECT_FALSE(band.moved(queued.state, last_sent->state)) << ms;
      }
    }
  }
  // The walk exercised both sides of the band.
  EXPECT_GT(moved_sends, 300);
  EXPECT_GT(held, 300);
  EXPECT_EQ(loop.channel().telemetry[0].states_queued.load(), static_cast<uint64_t>(sent));
  EXPECT_EQ(loop.channel().telemetry[0].states_held.load(), static_cast<uint64_t>(held));
}

TEST(DeadbandLoop, TwoDevicesAreJudgedSeparately) {
  // Device 0 still, device 1 moving: device 1 sends every send tick, device 0 only keepalives.
  LoopRig loop(2);
  std::array<int, 2> sent{}, held{};
  for (int ms = 0; ms < 500; ++ms) {
    loop.device(1).state.position.y -= 1e-4;
    const std::vector<TimedState> queued = loop.tick(ms);
    ASSERT_EQ(queued.size(), ms % 2 == 0 ? 2u : 0u);
    for (const TimedState& s : queued) {
      ASSERT_LT(s.state.device_index, 2);
      (s.send ? sent : held)[s.state.device_index] += 1;
    }
  }
  EXPECT_EQ(sent[0], 10);  // at 0, 50, ..., 450 ms
  EXPECT_EQ(held[0], 240);
  EXPECT_EQ(sent[1], 250);
  EXPECT_EQ(held[1], 0);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(loop.channel().telemetry[i].states_queued.load(), static_cast<uint64_t>(sent[i]));
    EXPECT_EQ(loop.channel().telemetry[i].states_held.load(), static_cast<uint64_t>(held[i]));
  }
}

}  // namespace
}  // namespace incise::devices::agent
