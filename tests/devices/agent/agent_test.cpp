// The haptic bridge end to end, in-process: the real Agent (haptic loop thread, StationLink on
// an io thread) against the in-test server, with a RecordingDevice to see what reaches the hand.

#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>

#include <chrono>
#include <cmath>
#include <functional>
#include <iostream>
#include <memory>
#include <thread>

#include "devices/agent/agent.h"
#include "fake_station_server.h"
#include "recording_device.h"
#include "tests/support/impaired_link.h"

namespace incise::devices::agent::testing {
namespace {

using namespace std::chrono_literals;

bool wait_until(const std::function<bool()>& condition, Clock::duration timeout) {
  const auto deadline = Clock::now() + timeout;
  while (!condition()) {
    if (Clock::now() >= deadline) return false;
    std::this_thread::sleep_for(2ms);
  }
  return true;
}

// The model the server sends, and what it must produce at the device's tip:
// F0 - K dx = (0, 0, 3) - diag(500, 500, 1000) (0.002, -0.001, -0.002) = (-1, 0.5, 5) N.
ForceModel server_model() {
  ForceModel m;
  m.reference_position = {0.04, 0.04, 0.031};
  m.force = {0.0, 0.0, 3.0};
  m.stiffness = {500, 0, 0, 0, 500, 0, 0, 0, 1000};
  m.sim_time_s = 1.0;
  return m;
}
constexpr Vec3 kTip = {0.042, 0.039, 0.029};
constexpr Vec3 kExpected = {-1.0, 0.5, 5.0};

bool near(const Vec3& a, const Vec3& b) {
  return std::abs(a.x - b.x) < 1e-12 && std::abs(a.y - b.y) < 1e-12 && std::abs(a.z - b.z) < 1e-12;
}

// An Agent with its io_context on a thread of its own, as main() runs it.
struct RunningAgent {
  RunningAgent(const std::string& url, Device& device) {
    AgentOptions options;
    options.server = *parse_server_url(url).value;
    options.token = "good-token";
    options.rate_hz = 500.0;
    // The plumbing: the model's force exactly, every state sent (the guard and the deadband
    // have tests of their own).
    options.guard = ForceGuardSettings::transparent();
    options.deadband = false;
    agent = std::make_unique<Agent>(io, options, std::vector<Device*>{&device});
    agent->start();
    thread = std::thread([this] { io.run(); });
  }
  void stop() {
    agent->request_stop();
    thread.join();
    agent->finish();
  }
  boost::asio::io_context io{1};
  std::unique_ptr<Agent> agent;
  std::thread thread;
};

TEST(HapticBridge, StreamsStatesAndRendersTheServersForceModels) {
  RecordingDevice device;
  device.set_position(kTip);
  FakeStationBehaviour behaviour;
  behaviour.force_model = server_model();
  behaviour.session_notice = build_session_notice({3, "running"});
  auto server = std::make_unique<FakeStationServer>(behaviour);
  RunningAgent running(server->url(), device);

  ASSERT_TRUE(wait_until([&] { return near(device.last_force(), kExpected); }, 3s))
      << "last force " << device.last_force().x << ", " << device.last_force().y << ", "
      << device.last_force().z;

  // The state rate, over a second.
  const std::size_t before = server->record().frames.size();
  const auto start = Clock::now();
  std::this_thread::sleep_for(1s);
  const double rate = (server->record().frames.size() - before) /
                      std::chrono::duration<double>(Clock::now() - start).count();
  EXPECT_GE(rate, 250.0);
  EXPECT_LE(rate, 550.0);
  // Still rendering (a loaded machine may starve the fake server for more than the model gap
  // now and then: the watchdog fades out and back, so allow a moment to be back).
  EXPECT_TRUE(wait_until([&] { return near(device.last_force(), kExpected); }, 500ms));

  // The server goes away: the force fades to exactly zero (within 10 ticks of the drop; the
  // bound here only allows for a slow machine noticing the drop).
  server.reset();
  const auto dropped = Clock::now();
  ASSERT_TRUE(wait_until([&] { return device.last_force() == Vec3{}; }, 1s));
  const auto fade_ms = std::chrono::duration<double, std::milli>(Clock::now() - dropped).count();
  running.stop();
  std::cout << "force reached zero " << fade_ms << " ms after the server went away\n";

  const BridgeStats& stats = running.agent->bridge_stats();
  EXPECT_GT(stats.states_sent, 250u);
  EXPECT_GT(stats.models_received, 100u);
  EXPECT_EQ(stats.round_trip_us.count(), stats.models_received);  // each echoes one of ours
  EXPECT_LT(stats.round_trip_us.percentile(50), 50000u);          // localhost: well under 50 ms
  EXPECT_GE(running.agent->loop_summary().periods, 500u);
}

TEST(HapticBridge, AMalformedForceModelClosesTheLinkWith1007) {
  RecordingDevice device;
  FakeStationBehaviour behaviour;
  behaviour.force_model = server_model();
  behaviour.bad_model_after = 20;
  FakeStationServer server(behaviour);
  RunningAgent running(server.url(), device);
  ASSERT_TRUE(wait_until([&] { return server.record().connections >= 2; }, 3s));
  running.stop();
  const FakeStationRecord record = server.record();
  ASSERT_FALSE(record.agent_close_codes.empty());
  EXPECT_EQ(record.agent_close_codes[0], 1007);
  EXPECT_EQ(record.agent_close_reasons[0], "|force| 150 N exceeds 100 N");
  EXPECT_TRUE(record.errors.empty()) << record.errors.front();
}

// The agent rendering the fake server's model, with an impairment proxy between them.
struct ProxiedAgent {
  ProxiedAgent() { device.set_position(kTip); }
  RecordingDevice device;
  FakeStationServer server{[] {
    FakeStationBehaviour behaviour;
    behaviour.force_model = server_model();
    return behaviour;
  }()};
  ImpairedLink link{"127.0.0.1", server.port(), {}};
  RunningAgent running{"ws://127.0.0.1:" + std::to_string(link.port()) + "/agent", device};
};

// Commands from the from-th to the first zero force (the device's record, one per loop tick).
std::size_t commands_until_zero(const RecordingDevice& device, std::size_t from) {
  const std::size_t end = std::min(device.force_count(), RecordingDevice::kCapacity);
  for (std::size_t i = from; i < end; ++i) {
    if (device.force(i) == Vec3{}) return i - from + 1;
  }
  return end - from;
}
// The loop ticks at 1 kHz (states go at 500 Hz): 15 ms without a model is 15 ticks, the fade 10,
// plus 3 for a model (one per state, every 2 ms) already in flight when the test acts.
constexpr std::size_t kMaxCommandsToZero = 15 + 10 + 3;

// A cable pull between agent and server (the proxy resets both connections): the watchdog
// fades the hand's force to exactly zero within 10 ticks of the agent seeing the link end.
TEST(HapticBridge, ALinkCutFadesTheForceToZeroWithinTenMilliseconds) {
  ProxiedAgent proxied;
  RecordingDevice& device = proxied.device;
  ImpairedLink& link = proxied.link;
  ASSERT_TRUE(wait_until([&] { return near(device.last_force(), kExpected); }, 3s));

  const std::size_t before_cut = device.force_count();
  link.cut();
  // Zero force within the fade (10 ticks) after the agent notices the reset, which is at once.
  // Counted in the loop's own commands, not in wall time, which a loaded machine stretches: even
  // if the io thread were slow to notice, the watchdog would start the fade 15 ms (15 ticks) after
  // the last model, so at most 15 + 10 ticks plus a model already in flight.
  ASSERT_TRUE(wait_until([&] { return device.last_force() == Vec3{}; }, 1s));
  EXPECT_LE(commands_until_zero(device, before_cut), kMaxCommandsToZero);
  // The force came down in steps of a tenth, never up: from the first smaller force to zero in
  // at most 10 commands.
  std::size_t first_lower = 0;
  std::size_t first_zero = 0;
  const std::size_t end = std::min(device.force_count(), RecordingDevice::kCapacity);
  for (std::size_t i = before_cut; i < end; ++i) {
    const Vec3 f = device.force(i);
    if (!first_lower && std::abs(f.z) < std::abs(kExpected.z) - 1e-9) first_lower = i;
    if (first_lower && f == Vec3{}) {
      first_zero = i;
      break;
    }
  }
  ASSERT_GT(first_lower, 0u);
  ASSERT_GT(first_zero, 0u);
  EXPECT_LE(first_zero - first_lower, 10u);
  proxied.running.stop();
}

// A silent cut (the cable is out, the socket does not notice: the proxy just stops delivering):
// no model for kModelMaxGap is a fault, so the force is gone 15 + 10 ms after the last model.
TEST(HapticBridge, ASilentCutFadesTheForceToZeroWithinTwentyFiveMsOfTheLastModel) {
  ProxiedAgent proxied;
  RecordingDevice& device = proxied.device;
  ImpairedLink& link = proxied.link;
  ASSERT_TRUE(wait_until([&] { return near(device.last_force(), kExpected); }, 3s));

  // From now on every frame takes a minute: nothing more arrives, nothing is closed.
  const std::size_t before_silence = device.force_count();
  link.set_impairment({.delay = std::chrono::seconds(60)});
  const auto silent_from = Clock::now();
  ASSERT_TRUE(wait_until([&] { return device.last_force() == Vec3{}; }, 1s));
  // 15 ms without a model, then 10 ticks of fade: never sooner, whatever the load...
  EXPECT_GE(Clock::now() - silent_from, 20ms);
  // ...and no later than that many of the loop's own ticks (a loaded machine stretches wall time,
  // not the count: the watchdog reads the clock, so a late tick only shortens the wait).
  EXPECT_LE(commands_until_zero(device, before_silence), kMaxCommandsToZero);
  proxied.running.stop();
}

}  // namespace
}  // namespace incise::devices::agent::testing
