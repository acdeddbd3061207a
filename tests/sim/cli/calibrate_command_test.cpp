// `incise calibrate` (sim/cli/calibrate_command.h) run as a user would, on the shipped cube and
// its example data: the modulus comes back into MATERIAL.json in a scene file's form, with a
// progress line per iteration; bad arguments and bad files are one error line, and no file.
#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/sim/cli_fixture.h"

namespace incise::sim {
namespace {

using nlohmann::json;
using test::CliRun;
using test::one_line;

class CalibrateCli : public test::CliFixture {};

constexpr const char* kData = "'" INCISE_SCENES_DIR "/calibration/cube_pushes.csv'";
constexpr const char* kScene = "'" INCISE_SCENES_DIR "/calibration/cube.json'";

TEST_F(CalibrateCli, FitsTheCubesModulusIntoAMaterialFile) {
  const CliRun run = incise(std::string("calibrate ") + kData + " " + kScene +
                            " --method lm --budget 100 --out material.json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.err, "");
  EXPECT_NE(run.out.find("iteration 1: misfit "), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("material.json: 1 parameter by lm"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("E[0] = 3600"), std::string::npos) << run.out;
  const json material = json::parse(test::read_file(dir_ / "material.json"));
  // The scene's "material" block: E fitted, the rest the scene's own.
  EXPECT_NEAR(material["material"]["E"].get<double>(), 3600, 3600 * 1e-8);
  EXPECT_EQ(material["material"]["model"], "mss");
  EXPECT_EQ(material["material"]["density"], 1040);
  EXPECT_EQ(material["material"]["damping"], 0.5);
  const json& c = material["calibration"];
  EXPECT_EQ(c["method"], "lm");
  EXPECT_EQ(c["parameters"], "label");
  EXPECT_LE(c["evaluations"].get<int>(), 100);
  EXPECT_EQ(c["fits"].size(), 5u);
  EXPECT_EQ(c["fits"][0]["measured"].size(), 200u);
  EXPECT_DOUBLE_EQ(c["values"][0]["start"].get<double>(), 2400);
  // The history never rises.
  const auto& history = c["history"];
  for (std::size_t k = 1; k < history.size(); ++k) {
    EXPECT_LE(history[k].get<double>(), history[k - 1].get<double>());
  }
}

TEST_F(CalibrateCli, RefusesBadArgumentsAndFilesWithOneLineAndWritesNothing) {
  write("bad.csv", "time_s,contact,x,y,z,dir_x,dir_y,dir_z\n0,0,0,0,0,0,0,1\n");
  const struct {
    std::string args;
    std::string error;
  } cases[] = {
      {std::string(kData) + " " + kScene + " --out m.json", "--method ga|cmaes|lm is required"},
      {std::string(kData) + " " + kScene + " --method sa --out m.json",
       "--method must be ga, cmaes or lm"},
      {std::string(kData) + " --method lm --out m.json",
       "calibrate needs a data file and a scene file"},
      {std::string(kData) + " " + kScene + " --method lm", "--out MATERIAL.json is required"},
      {std::string(kData) + " " + kScene + " --method lm --budget 0 --out m.json",
       "--budget must be a whole number from 1 to 10000000"},
      {std::string(kData) + " " + kScene + " --method lm --per tet --out m.json",
       "--per must be label or node"},
      {std::string(kData) + " " + kScene + " --method lm --smoothing -1 --out m.json",
       "--smoothing must be a number >= 0"},
      {std::string(kData) + " " + kScene + " --method lm --fast --out m.json",
       "unknown option --fast"},
      {std::string("bad.csv ") + kScene + " --method lm --out m.json",
       "bad.csv: line 1: missing column force_n"},
      {std::string("missing.csv ") + kScene + " --method lm --out m.json",
       "missing.csv: cannot read it"},
  };
  for (const auto& c : cases) {
    const CliRun run = incise("calibrate " + c.args);
    EXPECT_EQ(run.exit_code, 2) << c.args;
    EXPECT_TRUE(one_line(run.err)) << run.err;
    EXPECT_NE(run.err.find("incise: " + c.error), std::string::npos) << run.err;
    EXPECT_FALSE(std::filesystem::exists(dir_ / "m.json")) << c.args;
  }
}

}  // namespace
}  // namespace incise::sim
