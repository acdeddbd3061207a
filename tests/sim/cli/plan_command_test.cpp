// `incise plan` (sim/cli/plan_command.h) run as a user would, on the shipped liver scene: a path
// across the organ that goes round it rather than through, and precise usage errors.
#include <cmath>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sim/core/types.h"
#include "tests/sim/cli_fixture.h"

namespace incise::sim {
namespace {

using nlohmann::json;
using test::CliRun;
using test::one_line;

class PlanCli : public test::CliFixture {};

Vec3 point(const json& p) {
  return Vec3(p.at(0).get<double>(), p.at(1).get<double>(), p.at(2).get<double>());
}

TEST_F(PlanCli, APathAcrossTheLiverGoesRoundItRatherThanThrough) {
  // From one side of the 16 cm organ to the other, straight through its middle.
  const CliRun run = incise("plan '" INCISE_SCENES_DIR
                            "/surgery/liver_surgery.json' --from -0.12,0,0.01 --to 0.12,0,0.01 "
                            "--degree 3 --out path.json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(one_line(run.out)) << run.out;
  EXPECT_EQ(run.err, "");
  const json path = json::parse(test::read_file(dir_ / "path.json"));
  EXPECT_EQ(path.at("scene"), "liver");
  EXPECT_EQ(path.at("degree"), 3);
  EXPECT_EQ(path.at("coefficients").size(), 2u);
  ASSERT_EQ(path.at("path").size(), 65u);
  EXPECT_LT((point(path.at("path").front()) - Vec3(-0.12, 0, 0.01)).norm(), 1e-12);
  EXPECT_LT((point(path.at("path").back()) - Vec3(0.12, 0, 0.01)).norm(), 1e-12);
  // The straight line runs through the liver; the planned path costs a small fraction of it and
  // enters the liver a couple of millimetres at most (the probe is 2 mm).
  EXPECT_GT(path.at("straight_cost").get<double>(), 0);
  EXPECT_LT(path.at("cost").get<double>(), 0.1 * path.at("straight_cost").get<double>());
  EXPECT_LT(path.at("max_penetration").get<double>(), 0.004);
  EXPECT_TRUE(path.at("within_bound").get<bool>());
  // Its tissues: the liver, and the protected gallbladder bed.
  bool liver = false, bed = false;
  for (const auto& o : path.at("obstacles")) {
    liver |= o.at("name") == "liver" && o.at("points").get<int>() > 1000;
    bed |= o.at("name") == "gallbladder bed" && o.at("protected").get<bool>();
  }
  EXPECT_TRUE(liver && bed) << path.at("obstacles").dump();
}

TEST_F(PlanCli, BadArgumentsAreOneLineAndExitTwo) {
  const std::string scene = "'" INCISE_SCENES_DIR "/surgery/liver_surgery.json'";
  const struct {
    std::string arguments, message;
  } cases[] = {
      {"plan " + scene + " --to 0.1,0,0 --out p.json", "--from needs a point x,y,z in metres"},
      {"plan " + scene + " --from 0,0 --to 0.1,0,0 --out p.json",
       "--from needs a point x,y,z in metres"},
      {"plan " + scene + " --from 0,0,nan --to 0.1,0,0 --out p.json",
       "--from needs a point x,y,z in metres"},
      {"plan " + scene + " --from 0,0,0 --to 0,0,0 --out p.json",
       "--from and --to are the same point"},
      {"plan " + scene + " --from 0,0,0 --to 0.1,0,0 --degree 9 --out p.json",
       "--degree needs a whole number from 2 to 7"},
      {"plan " + scene + " --from 0,0,0 --to 0.1,0,0 --bound -1 --out p.json",
       "--bound needs metres in [0, 0.05]"},
      {"plan " + scene + " --from 0,0,0 --to 0.1,0,0", "plan needs --out PATH.json"},
      {"plan missing.json --from 0,0,0 --to 0.1,0,0 --out p.json", "missing.json"},
  };
  for (const auto& c : cases) {
    const CliRun run = incise(c.arguments);
    EXPECT_EQ(run.exit_code, 2) << c.arguments;
    EXPECT_TRUE(one_line(run.err)) << run.err;
    EXPECT_NE(run.err.find(c.message), std::string::npos) << run.err;
    EXPECT_FALSE(std::filesystem::exists(dir_ / "p.json")) << c.arguments;
  }
}

}  // namespace
}  // namespace incise::sim
