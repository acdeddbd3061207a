// The scripted device: devices/simulated_device.h.

#include "devices/simulated_device.h"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <stdexcept>

#include "devices/protocol.h"

namespace incise::devices {
namespace {

SimulatedScript make_script(bool loop, double jitter, uint64_t seed = 1) {
  SimulatedScript s;
  s.seed = seed;
  s.loop = loop;
  s.jitter = jitter;
  const double c = std::sqrt(0.5);
  s.orientation = {c, 0.0, c, 0.0};
  s.waypoints = {{0.0, {0.0, 0.0, 0.1}, 0.0},
                 {1.0, {0.02, 0.0, 0.08}, 1.0},
                 {1.5, {0.02, -0.01, 0.08}, 0.25},
                 {4.0, {-0.03, 0.01, 0.12}, 0.0}};
  return s;
}

void expect_near(const Vec3& a, const Vec3& b, double tolerance) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

bool bit_equal(const DeviceState& a, const DeviceState& b) {
  return std::bit_cast<std::array<uint64_t, 3>>(a.position) ==
             std::bit_cast<std::array<uint64_t, 3>>(b.position) &&
         std::bit_cast<uint32_t>(a.jaw) == std::bit_cast<uint32_t>(b.jaw) &&
         a.orientation == b.orientation;
}

TEST(SimulatedDevice, PassesThroughItsWaypointsAtTheirTimes) {
  SimulatedDevice device(make_script(false, 0.0));
  for (const Waypoint& w : device.script().waypoints) {
    SCOPED_TRACE(w.t);
    const DeviceState s = device.poll(w.t);
    expect_near(s.position, w.position, 1e-12);
    EXPECT_FLOAT_EQ(s.jaw, static_cast<float>(w.jaw));
  }
}

TEST(SimulatedDevice, InterpolatesLinearlyBetweenWaypoints) {
  SimulatedDevice device(make_script(false, 0.0));
  const DeviceState quarter = device.state_at(0.25);
  expect_near(quarter.position, {0.005, 0.0, 0.095}, 1e-12);
  EXPECT_FLOAT_EQ(quarter.jaw, 0.25f);
  const DeviceState mid = device.state_at(1.25);
  expect_near(mid.position, {0.02, -0.005, 0.08}, 1e-12);
  EXPECT_FLOAT_EQ(mid.jaw, 0.625f);
}

TEST(SimulatedDevice, HoldsTheEndsWithoutLoop) {
  SimulatedDevice device(make_script(false, 0.0));
  expect_near(device.state_at(-3.0).position, {0.0, 0.0, 0.1}, 0.0);
  expect_near(device.state_at(4.0).position, {-0.03, 0.01, 0.12}, 0.0);
  expect_near(device.state_at(100.0).position, {-0.03, 0.01, 0.12}, 0.0);
}

TEST(SimulatedDevice, LoopsWithTheLastWaypointsTimeAsPeriod) {
  SimulatedDevice device(make_script(true, 0.0));
  for (double t = 0.0; t < 4.0; t += 0.037) {
    SCOPED_TRACE(t);
    const DeviceState first = device.state_at(t);
    for (int lap = 1; lap <= 3; ++lap) {
      const DeviceState later = device.state_at(t + 4.0 * lap);
      expect_near(later.position, first.position, 1e-9);
      EXPECT_NEAR(later.jaw, first.jaw, 1e-6);
    }
  }
  expect_near(device.state_at(4.0).position, {0.0, 0.0, 0.1}, 1e-12);  // wrapped to t = 0
}

TEST(SimulatedDevice, IsDeterministicForASeed) {
  SimulatedDevice a(make_script(true, 0.001, 99));
  SimulatedDevice b(make_script(true, 0.001, 99));
  for (int i = 0; i < 2000; ++i) {
    const double t = i * 0.001 * 7;
    ASSERT_TRUE(bit_equal(a.poll(t), b.poll(t))) << t;
  }
}

TEST(SimulatedDevice, JitterDependsOnTheSeedAndStaysWithinItsAmplitude) {
  const double jitter = 0.001;
  SimulatedDevice clean(make_script(false, 0.0));
  SimulatedDevice one(make_script(false, jitter, 1));
  SimulatedDevice two(make_script(false, jitter, 2));
  int differing = 0;
  double largest = 0.0;
  for (int i = 0; i < 1000; ++i) {
    const double t = i * 0.004;
    const DeviceState c = clean.poll(t), s1 = one.poll(t), s2 = two.poll(t);
    if (!bit_equal(s1, s2)) ++differing;
    for (double d : {s1.position.x - c.position.x, s1.position.y - c.position.y,
                     s1.position.z - c.position.z}) {
      EXPECT_LE(std::abs(d), jitter);
      largest = std::max(largest, std::abs(d));
    }
    EXPECT_EQ(s1.jaw, c.jaw);  // jitter moves the tip only
  }
  EXPECT_GT(differing, 990);
  EXPECT_GT(largest, 0.5 * jitter);  // the tremor is really there
}

TEST(SimulatedDevice, JitterIsSmoothInTime) {
  SimulatedDevice device(make_script(false, 0.001, 5));
  SimulatedDevice clean(make_script(false, 0.0));
  // Knots 50 ms apart, values in [-1, 1): the tremor moves at most 2 * jitter / 50 ms.
  const double dt = 0.001;
  const double max_step = 2.0 * 0.001 * dt / 0.05 + 1e-12;
  for (double t = 0.0; t < 1.0; t += dt) {
    const double now = device.state_at(t).position.x - clean.state_at(t).position.x;
    const double next = device.state_at(t + dt).position.x - clean.state_at(t + dt).position.x;
    ASSERT_LE(std::abs(next - now), max_step) << t;
  }
}

TEST(SimulatedDevice, OrientationIsConstantAndEveryStateIsValidOnTheWire) {
  const auto script = parse_simulated_script(default_simulated_script());
  ASSERT_TRUE(script);
  SimulatedDevice device(*script.value);
  std::array<uint8_t, kDeviceStateFrameSize> frame{};
  for (int i = 0; i < 4000; ++i) {  // two laps of the default script at 100 Hz
    const DeviceState s = device.poll(i * 0.01);
    EXPECT_EQ(s.orientation, script.value->orientation);
    ASSERT_EQ(encode(s, i, i, frame), frame.size());
    const DecodeResult decoded = decode(frame);
    ASSERT_TRUE(decoded.ok()) << decoded.reason();
  }
}

TEST(SimulatedDevice, DescribesItself) {
  SimulatedDevice device(make_script(false, 0.0), "simulated (test)");
  EXPECT_EQ(device.name(), "simulated (test)");
  EXPECT_EQ(device.degrees_of_freedom(), 7);
  EXPECT_FALSE(device.capabilities().has_force_output);
  EXPECT_TRUE(device.capabilities().has_jaw);
  Device& generic = device;
  generic.set_force({1.0, 2.0, 3.0});  // no force output: ignored
  expect_near(generic.poll(1.0).position, {0.02, 0.0, 0.08}, 1e-12);
}

TEST(SimulatedDevice, RejectsAnInvalidScript) {
  SimulatedScript empty;
  EXPECT_THROW(SimulatedDevice{empty}, std::invalid_argument);
  SimulatedScript backwards = make_script(false, 0.0);
  backwards.waypoints[2].t = 0.5;
  try {
    SimulatedDevice device(backwards);
    FAIL() << "accepted waypoints out of order";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "simulated device script: waypoints[2].t: must be greater than the previous "
                 "waypoint's t (1), got 0.5");
  }
}

}  // namespace
}  // namespace incise::devices
