// Simulated-device scripts: devices/simulated_script.h.

#include "devices/simulated_script.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "devices/simulated_device.h"

namespace incise::devices {
namespace {

TEST(SimulatedScript, DefaultScriptIsValidAndLoops) {
  const auto parsed = parse_simulated_script(default_simulated_script());
  ASSERT_TRUE(parsed) << parsed.error;
  const SimulatedScript& script = *parsed.value;
  EXPECT_TRUE(script.loop);
  EXPECT_GT(script.jitter, 0.0);
  ASSERT_GE(script.waypoints.size(), 2u);
  EXPECT_EQ(script.waypoints.front().position, script.waypoints.back().position);
  EXPECT_EQ(check_simulated_script(script), "");
}

// The demo scene (sim/): a tissue block over x, y in [0, 0.08] m, z in [0, 0.03] m, probed by a
// tool tip sphere of radius 0.005 m; station frame = scene frame.
constexpr double kBlockSide = 0.08;
constexpr double kBlockTop = 0.03;
constexpr double kTipRadius = 0.005;

TEST(SimulatedScript, DefaultScriptPressesAndSlidesOnTheDemoTissue) {
  const auto parsed = parse_simulated_script(default_simulated_script());
  ASSERT_TRUE(parsed) << parsed.error;
  EXPECT_EQ(parsed.value->waypoints.back().t, 20.0);  // the loop period
  SimulatedDevice device(*parsed.value);
  const DeviceState start = device.state_at(0.0);
  EXPECT_NEAR(start.position.x, 0.04, 1e-3);
  EXPECT_NEAR(start.position.y, 0.04, 1e-3);
  EXPECT_NEAR(start.position.z, 0.06, 1e-3);

  double deepest = 1.0;
  double sliding = 0.0;  // tip path length while in contact [m]
  float widest_jaw = 0.0f;
  std::vector<Vec3> touch_downs;  // where each contact began
  bool in_contact = false;
  Vec3 previous = start.position;
  for (int ms = 0; ms <= 20000; ++ms) {
    const DeviceState s = device.state_at(ms * 1e-3);
    const Vec3& p = s.position;
    // Always over the block, never deeper than the intended ~6 mm (plus tremor).
    ASSERT_GE(p.x, 0.0) << ms;
    ASSERT_LE(p.x, kBlockSide) << ms;
    ASSERT_GE(p.y, 0.0) << ms;
    ASSERT_LE(p.y, kBlockSide) << ms;
    ASSERT_GE(p.z, kBlockTop + kTipRadius - 0.0065) << ms;
    const bool contact = p.z < kBlockTop + kTipRadius;
    if (contact && !in_contact) touch_downs.push_back(p);
    if (contact && in_contact) sliding += std::hypot(p.x - previous.x, p.y - previous.y);
    in_contact = contact;
    previous = p;
    deepest = std::min(deepest, p.z);
    widest_jaw = std::max(widest_jaw, s.jaw);
  }
  EXPECT_NEAR(deepest, 0.029, 0.0004);  // 6 mm overlap, give or take the tremor
  EXPECT_GE(sliding, 0.04);             // two slides of a few cm
  ASSERT_GE(touch_downs.size(), 2u);
  double farthest = 0.0;  // between touch-downs: pressed in two places
  for (const Vec3& p : touch_downs) {
    farthest = std::max(farthest, std::hypot(p.x - touch_downs[0].x, p.y - touch_downs[0].y));
  }
  EXPECT_GE(farthest, 0.02);
  EXPECT_GE(widest_jaw, 0.5f);  // and still grasps
}

TEST(SimulatedScript, OptionalKeysHaveDefaults) {
  const auto parsed = parse_simulated_script(R"({"waypoints": [{"t": 0, "position": [1, 2, 3]}]})");
  ASSERT_TRUE(parsed) << parsed.error;
  const SimulatedScript& s = *parsed.value;
  EXPECT_EQ(s.seed, 0u);
  EXPECT_FALSE(s.loop);
  EXPECT_EQ(s.jitter, 0.0);
  EXPECT_EQ(s.orientation, (Quat{1, 0, 0, 0}));
  ASSERT_EQ(s.waypoints.size(), 1u);
  EXPECT_EQ(s.waypoints[0].position, (Vec3{1, 2, 3}));
  EXPECT_EQ(s.waypoints[0].jaw, 0.0);
}

TEST(SimulatedScript, AllKeysAreRead) {
  const auto parsed = parse_simulated_script(R"({
    "seed": 42, "loop": true, "jitter": 0.001, "orientation": [0, 1, 0, 0],
    "waypoints": [{"t": 0, "position": [0, 0, 0], "jaw": 0.25},
                  {"t": 2.5, "position": [0.1, -0.2, 0.3], "jaw": 1}]})");
  ASSERT_TRUE(parsed) << parsed.error;
  const SimulatedScript& s = *parsed.value;
  EXPECT_EQ(s.seed, 42u);
  EXPECT_TRUE(s.loop);
  EXPECT_EQ(s.jitter, 0.001);
  EXPECT_EQ(s.orientation, (Quat{0, 1, 0, 0}));
  ASSERT_EQ(s.waypoints.size(), 2u);
  EXPECT_EQ(s.waypoints[1].t, 2.5);
  EXPECT_EQ(s.waypoints[1].position, (Vec3{0.1, -0.2, 0.3}));
  EXPECT_EQ(s.waypoints[0].jaw, 0.25);
  EXPECT_EQ(s.waypoints[1].jaw, 1.0);
}

struct BadScript {
  const char* json;
  const char* error;
};

// Each script breaks exactly one rule; the error names the key path and the problem.
const BadScript kBadScripts[] = {
    {R"([1, 2])", "(script): must be an object, got array"},
    {R"({"loop": true})", "waypoints: missing"},
    {R"({"waypoints": 3})", "waypoints: must be an array, got number"},
    {R"({"waypoints": []})", "waypoints: must have at least one waypoint"},
    {R"({"waypoint": [], "waypoints": [{"t": 0, "position": [0, 0, 0]}]})",
     "waypoint: unknown key (expected seed, loop, jitter, orientation or waypoints)"},
    {R"({"seed": -3, "waypoints": [{"t": 0, "position": [0, 0, 0]}]})",
     "seed: must be a non-negative integer, got -3"},
    {R"({"seed": "7", "waypoints": [{"t": 0, "position": [0, 0, 0]}]})",
     "seed: must be a non-negative integer, got string"},
    {R"({"loop": 1, "waypoints": [{"t": 0, "position": [0, 0, 0]}]})",
     "loop: must be true or false, got number"},
    {R"({"jitter": 0.5, "waypoints": [{"t": 0, "position": [0, 0, 0]}]})",
     "jitter: must be in [0, 0.01] m, got 0.5"},
    {R"({"jitter": -0.001, "waypoints": [{"t": 0, "position": [0, 0, 0]}]})",
     "jitter: must be in [0, 0.01] m, got -0.001"},
    {R"({"orientation": [1, 0, 0], "waypoints": [{"t": 0, "position": [0, 0, 0]}]})",
     "orientation: must have 4 numbers, got 3"},
    {R"({"orientation": [1, 1, 0, 0], "waypoints": [{"t": 0, "position": [0, 0, 0]}]})",
     "orientation: must be a unit quaternion, got |q| = 1.41421"},
    {R"({"waypoints": [{"t": 0, "position": [0, 0, 0]}, 5]})",
     "waypoints[1]: must be an object, got number"},
    {R"({"waypoints": [{"position": [0, 0, 0]}]})", "waypoints[0].t: missing"},
    {R"({"waypoints": [{"t": 0}]})", "waypoints[0].position: missing"},
    {R"({"waypoints": [{"t": "0", "position": [0, 0, 0]}]})",
     "waypoints[0].t: must be a number, got string"},
    {R"({"waypoints": [{"t": 0, "position": [0, 0]}]})",
     "waypoints[0].position: must have 3 numbers, got 2"},
    {R"({"waypoints": [{"t": 0, "position": [0, 0, 0]}, {"t": 1, "position": [0, 0, "z"]}]})",
     "waypoints[1].position[2]: must be a number, got string"},
    {R"({"waypoints": [{"t": 0, "position": [0, 0, 0], "jaw": 1.5}]})",
     "waypoints[0].jaw: must be in [0, 1], got 1.5"},
    {R"({"waypoints": [{"t": 0, "position": [0, 0, 0], "speed": 1}]})",
     "waypoints[0].speed: unknown key (a waypoint has t, position and jaw)"},
    {R"({"waypoints": [{"t": -1, "position": [0, 0, 0]}]})",
     "waypoints[0].t: must be >= 0, got -1"},
    {R"({"waypoints": [{"t": 0, "position": [0, 0, 0]}, {"t": 2, "position": [0, 0, 0]},
                       {"t": 1.5, "position": [0, 0, 0]}]})",
     "waypoints[2].t: must be greater than the previous waypoint's t (2), got 1.5"},
    {R"({"waypoints": [{"t": 0, "position": [0, 0, 0]}, {"t": 0, "position": [0, 0, 0]}]})",
     "waypoints[1].t: must be greater than the previous waypoint's t (0), got 0"},
    {R"({"loop": true, "waypoints": [{"t": 0, "position": [0, 0, 0]}]})",
     "loop: needs the last waypoint at t > 0 (its t is the loop period)"},
};

TEST(SimulatedScript, EveryRuleHasItsOwnError) {
  for (const BadScript& bad : kBadScripts) {
    const auto parsed = parse_simulated_script(bad.json);
    EXPECT_FALSE(parsed) << bad.json;
    EXPECT_EQ(parsed.error, bad.error) << bad.json;
  }
}

TEST(SimulatedScript, SyntaxErrorsGiveLineAndColumn) {
  const auto parsed =
      parse_simulated_script("{\n  \"seed\": 1,\n  \"loop\": tru, \"jitter\": 0\n}");
  ASSERT_FALSE(parsed);
  EXPECT_TRUE(parsed.error.starts_with("not valid JSON: parse error at line 3, column"))
      << parsed.error;
}

}  // namespace
}  // namespace incise::devices
