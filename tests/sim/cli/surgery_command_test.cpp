// `incise surgery SCENE.json --script SCRIPT.json --out RESULT.json` through the real binary
// (INCISE_CLI_PATH): the shipped liver scene cut along its marked line by the shipped script, and
// bad input rejected with exit code 2 and one stderr line naming the file and the JSON path.

#include <cmath>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/sim/cli_fixture.h"

namespace incise::sim {
namespace {

using nlohmann::json;
using test::CliRun;
using test::one_line;

class SurgeryCli : public test::CliFixture {};

double metric(const json& result, const std::string& name) {
  for (const json& row : result.at("damage")) {
    if (row.at("name") == name) return row.at("value").get<double>();
  }
  ADD_FAILURE() << "no damage row " << name;
  return NAN;
}

TEST_F(SurgeryCli, TheLiverCutScriptCutsAlongTheMarkedLine) {
  const CliRun run = incise("surgery '" INCISE_SCENES_DIR
                            "/surgery/liver_surgery.json' --script '" INCISE_SCENES_DIR
                            "/surgery/scripts/liver_cut.json' --out result.json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.err, "");
  EXPECT_TRUE(one_line(run.out)) << run.out;
  EXPECT_NE(run.out.find("steps/s"), std::string::npos) << run.out;
  const json result = json::parse(test::read_file(dir_ / "result.json"));
  const json scene = json::parse(test::read_file(INCISE_SCENES_DIR "/surgery/liver_surgery.json"));
  const json script =
      json::parse(test::read_file(INCISE_SCENES_DIR "/surgery/scripts/liver_cut.json"));
  EXPECT_EQ(result.at("scene"), "liver");
  EXPECT_EQ(result.at("finite"), true);
  EXPECT_EQ(result.at("status"), "completed");
  // The run covers the script: the fewest whole steps of dt that reach its duration.
  const double dt = result.at("dt").get<double>();
  const double duration = script.at("duration").get<double>();
  EXPECT_EQ(result.at("duration").get<double>(), duration);
  EXPECT_EQ(result.at("steps").get<long long>(), std::llround(std::ceil(duration / dt - 1e-9)));
  EXPECT_GT(result.at("steps_per_second").get<double>(), 0);
  EXPECT_GT(result.at("tets").get<int>(), 0);
  // Cut events by the scalpel (tool 2), none a never event.
  int cuts = 0;
  for (const json& e : result.at("events")) {
    EXPECT_NE(e.at("kind"), "never_event") << e.dump();
    if (e.at("kind") == "cut") {
      ++cuts;
      EXPECT_EQ(e.at("tool"), 2);
      EXPECT_EQ(e.at("tool_kind"), "scalpel");
      EXPECT_GT(e.at("time").get<double>(), 0);
      EXPECT_LE(e.at("time").get<double>(), duration + dt);
    }
  }
  EXPECT_GT(cuts, 0);
  EXPECT_EQ(metric(result, "damage.cut_events"), cuts);
  EXPECT_GT(metric(result, "damage.cut_area"), 0);
  // On target: the cut's mean distance to the marked line is within the scene's half width.
  EXPECT_LT(metric(result, "damage.cut_mean_distance"),
            scene.at("damage").at("target_half_width").get<double>());
  EXPECT_EQ(metric(result, "damage.never_event"), 0);
  // One force model per device; the parked probe and grasper touch nothing.
  ASSERT_EQ(result.at("force_models").size(), 3u);
  EXPECT_EQ(result.at("force_models")[0].at("force"), json::parse("[0.0, 0.0, 0.0]"));
  EXPECT_GE(result.at("mass_scaled_nodes").get<int>(), 0);
  EXPECT_GE(result.at("cuts_refused").get<int>(), 0);
}

TEST_F(SurgeryCli, ABadSceneExitsTwoNamingTheFileAndThePath) {
  write("scene.json", R"({"anatomy": "liver", "tools": [{"kind": "probe", "device": 0},
                                                       {"kind": "saw", "device": 1}]})");
  write("script.json",
        R"({"duration": 0.01, "devices": [{"keyframes": [{"t": 0, "tip": [0, 0, 0.3]}]}]})");
  const CliRun run = incise("surgery scene.json --script script.json --out result.json");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.err,
            "incise: scene.json: tools[1].kind: \"saw\" is not one of probe, grasper, scalpel, "
            "scope\n");
  EXPECT_FALSE(std::filesystem::exists(dir_ / "result.json"));
}

// A coarse liver (test-only options) so that the script is checked against a real scene fast.
TEST_F(SurgeryCli, ABadScriptExitsTwoNamingTheFileAndThePath) {
  write("scene.json",
        R"({"anatomy": "liver", "anatomy_options": {"length": 0.08, "cell_size": 0.016}})");
  write("script.json",
        R"({"duration": 0.01, "devices": [{"keyframes": [{"t": 0, "at": "cut_middle"}]}]})");
  const CliRun run = incise("surgery scene.json --script script.json --out result.json");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_TRUE(one_line(run.err)) << run.err;
  EXPECT_EQ(
      run.err.rfind("incise: script.json: devices[0].keyframes[0].at: \"cut_middle\" is not a "
                    "place of the liver scene (one of: right_lobe, ",
                    0),
      0u)
      << run.err;
}

TEST_F(SurgeryCli, MissingArgumentsAreUsageErrors) {
  const CliRun no_script = incise("surgery scene.json --out result.json");
  EXPECT_EQ(no_script.exit_code, 2);
  EXPECT_TRUE(one_line(no_script.err));
  EXPECT_NE(no_script.err.find("surgery needs --script SCRIPT.json"), std::string::npos);
  const CliRun unknown = incise("surgery scene.json --script s.json --out r.json --fast");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("unknown option --fast"), std::string::npos);
}

}  // namespace
}  // namespace incise::sim
