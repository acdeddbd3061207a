// A tool script sampled in time: sim/surgery/track_sampling.h.
#include "sim/surgery/track_sampling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <nlohmann/json.hpp>

#include "script_fixtures.h"
#include "sim/surgery/tool_script.h"

namespace incise::sim::surgery {
namespace {

using nlohmann::json;
using testing::expect_near;
using testing::scripted_scene;

// Positions and the jaw linear, the direction normalised-lerped, held outside the keyframes; the
// orientation turns e_z onto the direction.
TEST(ToolScript, InterpolatesInClosedForm) {
  const ToolScript script = parse_tool_script(json::parse(R"({
    "duration": 1,
    "devices": [{"keyframes": [
      {"t": 0.1, "tip": [0, 0, 0], "direction": [2, 0, 0], "jaw": 1},
      {"t": 0.5, "tip": [0.04, -0.02, 0.01], "direction": [0, 3, 0], "jaw": 0}]}]})"),
                                              scripted_scene());
  ASSERT_EQ(script.devices.size(), 1u);
  const DeviceTrack& track = script.devices[0];
  const Vec3 b(0.04, -0.02, 0.01);
  const ToolInput mid = sample_track(track, 0.2);  // s = 1/4
  expect_near(mid.tip, 0.25 * b);
  expect_near(mid.orientation * Vec3::UnitZ(), Vec3(3, 1, 0) / std::sqrt(10.0));
  EXPECT_NEAR(mid.jaw, 0.75, 1e-15);
  const ToolInput before = sample_track(track, 0);
  expect_near(before.tip, Vec3::Zero());
  expect_near(before.orientation * Vec3::UnitZ(), Vec3::UnitX());
  EXPECT_EQ(before.jaw, 1);
  const ToolInput after = sample_track(track, 0.9);
  expect_near(after.tip, b);
  expect_near(after.orientation * Vec3::UnitZ(), Vec3::UnitY());
  EXPECT_EQ(after.jaw, 0);
  const ToolInput at_key = sample_track(track, 0.5);
  expect_near(at_key.tip, b);
  std::vector<ToolInput> inputs;
  sample_script(script, 0.2, inputs);
  ASSERT_EQ(inputs.size(), 1u);
  expect_near(inputs[0].tip, mid.tip);
}

}  // namespace
}  // namespace incise::sim::surgery
