// Tool scripts: sim/surgery/tool_script.h. Keyframes resolve their places and carry over what
// they leave out, and every bad input names its JSON path.
#include "sim/surgery/tool_script.h"

#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "script_fixtures.h"
#include "sim/scene/scene_error.h"

namespace incise::sim::surgery {
namespace {

using nlohmann::json;
using testing::expect_near;
using testing::scripted_scene;

struct BadCase {
  const char* json;
  const char* error;  // SceneError::what(): "<path>: <reason>"
};

// "at" + "offset", "towards", "along", "advance", the cut line's ends, and what carries over.
TEST(ToolScript, ResolvesPlacesAndCarriesDirectionAndJaw) {
  const ToolScript script = parse_tool_script(json::parse(R"({
    "duration": 2,
    "devices": [
      {"keyframes": [
        {"t": 0, "at": "horn", "offset": [0, 0, 0.01], "towards": "notch", "advance": 0.005,
         "jaw": 0.4},
        {"t": 1, "at": "cut_end"}]},
      {"keyframes": [{"t": 0, "at": "medial", "along": "medial", "advance": 0.01},
                     {"t": 2, "at": "cut_start"}]}]})"),
                                              scripted_scene());
  const Keyframe& first = script.devices[0].keyframes[0];
  const Vec3 base(0.01, 0, 0.01);
  const Vec3 towards = (Vec3(0, 0.02, 0) - base).normalized();
  expect_near(first.direction, towards);
  expect_near(first.tip, base + 0.005 * towards);
  EXPECT_EQ(first.jaw, 0.4);
  const Keyframe& second = script.devices[0].keyframes[1];
  expect_near(second.tip, Vec3(0.01, 0, 0));  // the cut line's last point
  expect_near(second.direction, towards);     // carried over
  EXPECT_EQ(second.jaw, 0.4);
  const Keyframe& portal = script.devices[1].keyframes[0];
  expect_near(portal.direction, -Vec3::UnitZ());
  expect_near(portal.tip, Vec3(0, 0, 0.04));
  EXPECT_EQ(portal.jaw, 1);  // the first keyframe's default: open
  expect_near(script.devices[1].keyframes[1].tip, Vec3(-0.01, 0, 0));
}

// "from": the tool entered through a place (a portal) and points from it to the tip; "advance"
// then goes on along that line (negative: stops short).
TEST(ToolScript, FromAPortalPointsThroughItToThePlace) {
  const ToolScript script = parse_tool_script(json::parse(R"({
    "duration": 1,
    "devices": [{"keyframes": [{"t": 0, "at": "horn", "from": "medial", "advance": -0.002}]}]})"),
                                              scripted_scene());
  const Keyframe& k = script.devices[0].keyframes[0];
  const Vec3 horn(0.01, 0, 0), portal(0, 0, 0.05);
  const Vec3 through = (horn - portal).normalized();
  expect_near(k.direction, through);
  expect_near(k.tip, horn - 0.002 * through);
  EXPECT_THROW(parse_tool_script(json::parse(R"({"duration": 1, "devices": [{"keyframes": [
                   {"t": 0, "at": "medial", "from": "medial"}]}]})"),
                                 scripted_scene()),
               SceneError);
}

TEST(ToolScript, EveryBadInputNamesItsPath) {
  const BadCase cases[] = {
      {R"([1])", "the script must be a JSON object (got [1])"},
      {R"({"devices": []})", "duration: is required"},
      {R"({"duration": 0, "devices": []})", "duration: must be > 0 (got 0)"},
      {R"({"duration": 1, "devices": []})", "devices: must be a non-empty array (got [])"},
      {R"({"duration": 1, "device": []})",
       "device: unknown key (expected one of: description, duration, devices)"},
      {R"({"duration": 1, "devices": [{"keyframes": []}]})",
       "devices[0].keyframes: must be a non-empty array (got [])"},
      {R"({"duration": 1, "devices": [{"keyframes": [{"t": 0, "tip": [0, 0, 0]}]},
                                      {"keyframes": [{"t": 0, "tip": [0, 0, 0]}]}, {}]})",
       "devices[2]: no tool of the test scene is on device 2"},
      {R"({"duration": 1, "devices": [{"keyframes": [{"t": 0, "tipp": [0, 0, 0]}]}]})",
       "devices[0].keyframes[0].tipp: unknown key (expected one of: t, tip, at, offset, "
       "direction, towards, from, along, advance, jaw)"},
      {R"({"duration": 1, "devices": [{"keyframes": [{"t": 2, "tip": [0, 0, 0]}]}]})",
       "devices[0].keyframes[0].t: must be in [0, 1] (got 2)"},
      {R"({"duration": 1, "devices": [{"keyframes": [{"t": 0.5, "tip": [0, 0, 0]},
                                                      {"t": 0.5, "tip": [0, 0, 0]}]}]})",
       "devices[0].keyframes[1].t: must be after the previous keyframe's (0.5) (got 0.5)"},
      {R"({"duration": 1, "devices": [{"keyframes": [{"t": 0, "tip": [0, 0]}]}]})",
       "devices[0].keyframes[0].tip: must be an array of 3 numbers (got [0,0])"},
      {R"({"duration": 1, "devices": [{"keyframes": [{"t": 0, "tip": [0, 0, 0], "at": "horn"}]}]})",
       R"(devices[0].keyframes[0]: has both "tip" and "at" (give one))"},
      {R"({"duration": 1, "devices": [{"keyframes": [{"t": 0, "jaw": 0}]}]})",
       R"(devices[0].keyframes[0]: needs "tip" or "at")"},
      {R"({"duration": 1, "devices": [{"keyframes": [{"t": 0, "tip": [0, 0, 0],
                                                      "offset": [0, 0, 1]}]}]})",
       R"(devices[0].keyframes[0].offset: belongs to "at" (a "tip" is already a point))"},
      {R"({"duration": 1, "devices": [{"keyframes": [{"t": 0, "at": "knob"}]}]})",
       R"(devices[0].keyframes[0].at: "knob" is not a place of the test scene (one of: horn, )"
       R"(notch, medial, cut_start, cut_end))"},
      {R"({"duration": 1, "devices": [{"keyframes": [{"t": 0, "at": "horn", "along": "horn"}]}]})",
       R"(devices[0].keyframes[0].along: "horn" is not a portal of the test scene (one of: )"
       R"(medial))"},
      {R"({"duration": 1, "devices": [{"keyframes": [{"t": 0, "at": "horn", "towards": "horn"}]}]})",
       "devices[0].keyframes[0].towards: is where the tip is"},
      {R"({"duration": 1, "devices": [{"keyframes": [{"t": 0, "at": "horn",
           "direction": [0, 0, 1], "towards": "notch"}]}]})",
       R"(devices[0].keyframes[0]: has more than one of "direction", "towards", "from", "along")"},
      {R"({"duration": 1, "devices": [{"keyframes": [{"t": 0, "tip": [0, 0, 0],
                                                      "direction": [0, 0, 0]}]}]})",
       "devices[0].keyframes[0].direction: must not be zero"},
      {R"({"duration": 1, "devices": [{"keyframes": [{"t": 0, "tip": [0, 0, 0]},
           {"t": 1, "tip": [0, 0, 0], "direction": [0, 0, 1]}]}]})",
       "devices[0].keyframes[1].direction: turns the tool round from the previous keyframe's "
       "direction (undefined halfway; add a keyframe between)"},
      {R"({"duration": 1, "devices": [{"keyframes": [{"t": 0, "tip": [0, 0, 0], "jaw": 1.5}]}]})",
       "devices[0].keyframes[0].jaw: must be in [0, 1] (got 1.5)"},
  };
  const SurgicalSceneSetup scene = scripted_scene();
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.json);
    try {
      parse_tool_script(json::parse(c.json), scene);
      ADD_FAILURE() << "accepted";
    } catch (const SceneError& error) {
      EXPECT_EQ(std::string(error.what()), c.error);
    }
  }
}

}  // namespace
}  // namespace incise::sim::surgery
