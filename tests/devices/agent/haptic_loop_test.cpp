// The haptic loop's tick and thread: devices/agent/haptic_loop.h. Ticks are driven with
// synthetic times, so fade and staleness are checked tick by tick without sleeping.

#include "devices/agent/haptic_loop.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "recording_device.h"
#include "tests/devices/allocation_counter.h"

namespace incise::devices::agent {
namespace {

using namespace std::chrono_literals;
using testing::RecordingDevice;

// F0 - K dx for the tip below: (1, -0.5, 2) - diag(200, 300, 400) (0.001, -0.002, -0.001)
//   = (0.8, 0.1, 2.4) N.
constexpr Vec3 kReference = {0.04, 0.04, 0.03};
constexpr Vec3 kTip = {0.041, 0.038, 0.029};
constexpr Vec3 kExpected = {0.8, 0.1, 2.4};

ForceModel test_model(int answers_state_at_ms = 0) {
  ForceModel m;
  m.state_timestamp_us = static_cast<uint64_t>(answers_state_at_ms) * 1000;
  m.reference_position = kReference;
  m.force = {1.0, -0.5, 2.0};
  m.stiffness = {200, 0, 0, 0, 300, 0, 0, 0, 400};
  return m;
}

void expect_scaled(const Vec3& f, double factor) {
  EXPECT_NEAR(f.x, factor * kExpected.x, 1e-12);
  EXPECT_NEAR(f.y, factor * kExpected.y, 1e-12);
  EXPECT_NEAR(f.z, factor * kExpected.z, 1e-12);
}

class HapticLoopTest : public ::testing::Test {
 protected:
  HapticLoopTest() {
    device_.set_position(kTip);
    loop_ = std::make_unique<HapticLoop>(device_, channel_, 2, t0_);
  }
  // Runs ticks at t0 + first_ms .. t0 + last_ms, one per ms.
  void run_ticks(int first_ms, int last_ms) {
    for (int ms = first_ms; ms <= last_ms; ++ms)
      loop_->tick(t0_ + std::chrono::milliseconds(ms));
  }

  const Clock::time_point t0_ = Clock::now();
  RecordingDevice device_;
  HapticChannel channel_;
  std::unique_ptr<HapticLoop> loop_;
};

TEST_F(HapticLoopTest, RendersTheModelAfterATenTickFadeIn) {
  channel_.link_up = true;
  channel_.models[0].publish({test_model(), t0_});
  for (int ms = 0; ms < 15; ++ms) {
    loop_->tick(t0_ + std::chrono::milliseconds(ms));
    expect_scaled(device_.last_force(), std::min(ms + 1, 10) / 10.0);
  }
  EXPECT_DOUBLE_EQ(device_.last_poll_t(), 0.014);
  EXPECT_EQ(device_.force_count(), 15u);
}

TEST_F(HapticLoopTest, LinkLossFadesToExactlyZeroInTenTicksAndBack) {
  channel_.link_up = true;
  channel_.models[0].publish({test_model(), t0_});
  run_ticks(0, 12);
  expect_scaled(device_.last_force(), 1.0);
  channel_.link_up = false;
  for (int i = 1; i <= 10; ++i) {
    loop_->tick(t0_ + std::chrono::milliseconds(12 + i));
    expect_scaled(device_.last_force(), (10 - i) / 10.0);
    EXPECT_EQ(loop_->fault(), GuardFault::LinkDown);
  }
  EXPECT_EQ(device_.last_force(), (Vec3{0.0, 0.0, 0.0}));  // exactly zero
  run_ticks(23, 40);
  EXPECT_EQ(device_.last_force(), (Vec3{}));
  // The link is back with a fresh model: the force ramps in again, no jump.
  channel_.link_up = true;
  channel_.models[0].publish({test_model(41), t0_ + 41ms});
  for (int i = 1; i <= 10; ++i) {
    loop_->tick(t0_ + std::chrono::milliseconds(40 + i));
    expect_scaled(device_.last_force(), i / 10.0);
  }
}

TEST_F(HapticLoopTest, WithoutModelsForFifteenMsTheForceFadesOut) {
  channel_.link_up = true;
  channel_.models[0].publish({test_model(), t0_});
  run_ticks(0, 15);  // the last model arrived 15 ms ago: the link is still alive
  expect_scaled(device_.last_force(), 1.0);
  for (int i = 1; i <= 10; ++i) {
    loop_->tick(t0_ + std::chrono::milliseconds(15 + i));
    expect_scaled(device_.last_force(), (10 - i) / 10.0);
    EXPECT_EQ(loop_->fault(), GuardFault::NoModel);
  }
  EXPECT_EQ(device_.last_force(), (Vec3{}));
  // A new model revives it.
  channel_.models[0].publish({test_model(26), t0_ + 26ms});
  run_ticks(26, 40);
  expect_scaled(device_.last_force(), 1.0);
}

TEST_F(HapticLoopTest, AModelAnsweringAStateOverThreeHundredMsOldFadesOut) {
  // Models keep arriving, but each answers the state of 300 ms earlier: a long delay, still
  // rendered.
  channel_.link_up = true;
  for (int ms = 300; ms <= 320; ++ms) {
    channel_.models[0].publish({test_model(ms - 300), t0_ + std::chrono::milliseconds(ms)});
    loop_->tick(t0_ + std::chrono::milliseconds(ms));
  }
  expect_scaled(device_.last_force(), 1.0);
  EXPECT_EQ(channel_.telemetry[0].model_age_us.load(), 300'000u);
  // From here on the delay grows past 300 ms: the models are stale on arrival.
  for (int i = 1; i <= 10; ++i) {
    const int ms = 320 + i;
    channel_.models[0].publish({test_model(ms - 310), t0_ + std::chrono::milliseconds(ms)});
    loop_->tick(t0_ + std::chrono::milliseconds(ms));
    expect_scaled(device_.last_force(), (10 - i) / 10.0);
    EXPECT_EQ(loop_->fault(), GuardFault::StaleModel);
  }
}

TEST_F(HapticLoopTest, AModelForAnotherDeviceIsNotRendered) {
  channel_.link_up = true;
  ForceModel other = test_model();
  other.device_index = 1;  // the recording device is index 0
  channel_.models[0].publish({other, t0_});
  run_ticks(0, 20);
  EXPECT_EQ(device_.last_force(), (Vec3{}));
}

TEST_F(HapticLoopTest, QueuesEveryKthStateWhileTheLinkIsUp) {
  run_ticks(0, 9);  // link down: nothing queued
  TimedState s;
  EXPECT_FALSE(channel_.states.pop(s));
  channel_.link_up = true;
  run_ticks(10, 19);  // ticks 10 .. 19; k = 2, so the even-numbered ones
  for (int ms = 10; ms < 20; ms += 2) {
    ASSERT_TRUE(channel_.states.pop(s));
    EXPECT_EQ(s.timestamp_us, static_cast<uint64_t>(ms) * 1000);
    EXPECT_EQ(s.state.position, kTip);
  }
  EXPECT_FALSE(channel_.states.pop(s));
}

TEST_F(HapticLoopTest, TickDoesNotAllocate) {
  channel_.link_up = true;
  channel_.models[0].publish({test_model(), t0_});
  run_ticks(0, 5);  // warm up
  const std::size_t before = incise::devices::testing::allocation_count();
  for (int ms = 6; ms < 2000; ++ms) {
    loop_->tick(t0_ + std::chrono::milliseconds(ms));
    if (ms % 10 == 0) {
      channel_.models[0].publish({test_model(ms), t0_ + std::chrono::milliseconds(ms)});
    }
    TimedState s;
    if (ms % 7 == 0) {
      while (channel_.states.pop(s)) {
      }
    }
  }
  EXPECT_EQ(incise::devices::testing::allocation_count(), before);
  expect_scaled(device_.last_force(), 1.0);
}

// The agent's own settings (guard, deadband) with two devices, a calibration and models that
// change: still no allocation per tick.
TEST(HapticLoopProduction, TwoDevicesWithTheGuardAndACalibrationDoNotAllocate) {
  RecordingDevice right;
  RecordingDevice left;
  right.set_position(kTip);
  left.set_position({0.02, 0.02, 0.03});
  HapticChannel channel;
  channel.link_up = true;
  const Clock::time_point t0 = Clock::now();
  Device* devices[] = {&right, &left};
  HapticLoop loop(devices, channel, LoopSettings{}, t0);
  WorkspaceMapping mapping;
  mapping.scale = 0.5;
  channel.mappings[1].publish(mapping);
  for (int ms = 0; ms < 5; ++ms)
    loop.tick(t0 + std::chrono::milliseconds(ms));
  const std::size_t before = incise::devices::testing::allocation_count();
  for (int ms = 5; ms < 2000; ++ms) {
    if (ms % 2 == 0) {
      ForceModel model = test_model(ms);
      channel.models[0].publish({model, t0 + std::chrono::milliseconds(ms)});
      model.device_index = 1;
      channel.models[1].publish({model, t0 + std::chrono::milliseconds(ms)});
    }
    if (ms == 1000) channel.mappings[0].publish(mapping);
    right.set_position({kTip.x + 1e-4 * (ms % 7), kTip.y, kTip.z});
    loop.tick(t0 + std::chrono::milliseconds(ms));
    TimedState s;
    while (channel.states.pop(s)) {
    }
  }
  EXPECT_EQ(incise::devices::testing::allocation_count(), before);
  // Both hands rendered a force at the end.
  EXPECT_NE(right.last_force(), (Vec3{}));
  EXPECT_NE(left.last_force(), (Vec3{}));
}

TEST(HapticLoopThread, RunsAtOneKilohertzAndFadesOutWhenStopped) {
  RecordingDevice device;
  device.set_position(kTip);
  HapticChannel channel;
  channel.link_up = true;
  HapticLoop loop(device, channel, 4, Clock::now());
  loop.start();
  const auto started = Clock::now();
  // Keep the model fresh, as a server answering the states would.
  while (Clock::now() - started < 300ms) {
    channel.models[0].publish({test_model(), Clock::now()});
    std::this_thread::sleep_for(5ms);
  }
  loop.stop();
  const LoopSummary s = loop.summary();
  // A shared, noisy machine: a descheduled thread skips ticks (lowering the rate), so only the
  // median and the upper bound of the rate are tight; the tails are not asserted.
  EXPECT_GE(s.periods, 150u);
  EXPECT_GE(s.rate_hz, 500.0);
  EXPECT_LE(s.rate_hz, 1005.0);  // deadlines are absolute: never faster than 1 kHz
  EXPECT_NEAR(s.period_p50_us, 1000.0, 100.0);
  // The last ten forces fade out by tenths and the device is left at exactly zero.
  const std::size_t n = device.force_count();
  ASSERT_GT(n, 12u);
  EXPECT_EQ(device.last_force(), (Vec3{}));
  for (int i = 1; i <= 10; ++i) {
    const Vec3 f = device.force(n - 1 - i);  // before the final explicit zero
    EXPECT_NEAR(f.z, (i - 1) / 10.0 * kExpected.z, 1e-12) << i;
  }
}

}  // namespace
}  // namespace incise::devices::agent
