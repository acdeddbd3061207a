// Runs the real incise binary (INCISE_CLI_PATH, from CMake) as a user would.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "sim/mesh/box_mesher.h"
#include "sim/mesh/msh_writer.h"

#include "tests/sim/cli_fixture.h"

namespace incise::sim {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::CliRun;
using test::one_line;

class Cli : public test::CliFixture {
 protected:
  static json small_scene() {
    return json::parse(R"({
      "mesh": {"box": {"size": [0.02, 0.02, 0.04], "cells": [2, 2, 4]}},
      "material": {"model": "mss", "E": 3000, "nu": 0.45, "density": 1000, "damping": 0.5},
      "constraints": [{"where": {"box": [[0, 0, 0], [0.02, 0.02, 0]]}, "fix": "xyz"}],
      "gravity": [0, 0, -9.81],
      "solver": {"integrator": "symplectic_euler", "dt": 1e-4, "steps": 3000}
    })");
  }
};

TEST_F(Cli, SolvesASceneAndWritesTheResult) {
  write("scene.json", small_scene().dump());
  const CliRun run = incise("solve scene.json --out result.json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.err, "");
  const json result = json::parse(test::read_file(dir_ / "result.json"));
  EXPECT_EQ(result.at("nodes"), 3 * 3 * 5);
  EXPECT_EQ(result.at("tets"), 5 * 2 * 2 * 4);
  EXPECT_EQ(result.at("rest").size(), 45u);
  EXPECT_EQ(result.at("displacement").size(), 45u);
  EXPECT_EQ(result.at("steps"), 3000);
  EXPECT_GT(result.at("ms_per_step").get<double>(), 0);
  EXPECT_EQ(result.at("finite"), true);
  EXPECT_EQ(result.at("status"), "completed");
  EXPECT_LT(result.at("max_speed").get<double>(), 1e-4);  // settled (peak is ~0.05 m/s)
  // The top corner (node 44) sags, the clamped base (node 0) stays.
  EXPECT_EQ(result.at("rest")[44], json::parse("[0.02, 0.02, 0.04]"));
  EXPECT_LT(result.at("displacement")[44][2].get<double>(), -1e-4);
  EXPECT_EQ(result.at("displacement")[0], json::parse("[0.0, 0.0, 0.0]"));
}

TEST_F(Cli, TheExampleSceneSettles) {
  const CliRun run = incise("solve '" INCISE_SCENES_DIR "/clamped_box.json' --out result.json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json result = json::parse(test::read_file(dir_ / "result.json"));
  EXPECT_EQ(result.at("finite"), true);
  EXPECT_LT(result.at("max_speed").get<double>(), 1e-6);
}

// The example adaptive scene (sim/scenes/adaptive_box.json): the column refines where it strains
// near its clamp; RESULT.json describes the final mesh, the original nodes first.
TEST_F(Cli, TheAdaptiveExampleRefinesAndReportsTheFinalMesh) {
  const CliRun run = incise("solve '" INCISE_SCENES_DIR "/adaptive_box.json' --out result.json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.err, "");
  const json result = json::parse(test::read_file(dir_ / "result.json"));
  EXPECT_EQ(result.at("finite"), true);
  EXPECT_EQ(result.at("steps"), 3000);
  const int box_tets = 5 * 2 * 2 * 4;
  const int box_nodes = 3 * 3 * 5;
  EXPECT_GT(result.at("tets").get<int>(), box_tets);
  const int nodes = result.at("nodes").get<int>();
  EXPECT_GT(nodes, box_nodes);
  EXPECT_EQ(result.at("rest").size(), static_cast<std::size_t>(nodes));
  EXPECT_EQ(result.at("displacement").size(), static_cast<std::size_t>(nodes));
  EXPECT_EQ(result.at("rest")[44], json::parse("[0.02, 0.02, 0.04]"));
  EXPECT_LT(result.at("displacement")[44][2].get<double>(), -1e-4);
  // Every vertex on the clamped base stays put; inserted ones sit at their host's interpolated
  // position, which is the rest point up to rounding.
  for (int i = 0; i < nodes; ++i) {
    if (result["rest"][i][2].get<double>() != 0) continue;
    for (int a = 0; a < 3; ++a)
      EXPECT_LT(std::abs(result["displacement"][i][a].get<double>()), 1e-15) << i;
  }

  json wrong = small_scene();
  wrong["solver"]["integrator"] = "central_difference";
  wrong["adaptivity"] = json::parse(R"({"l_min": 0.002, "fine_size": 0.004,
                                        "strain": {"on": 0.05, "off": 0.03}})");
  write("wrong.json", wrong.dump());
  const CliRun refused = incise("solve wrong.json --out r.json");
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_EQ(refused.err,
            "incise: wrong.json: adaptivity: needs solver.integrator \"symplectic_euler\" (got "
            "\"central_difference\")\n");
}

TEST_F(Cli, InvalidSceneGivesExitCode2AndOneLineNamingTheKey) {
  json scene = small_scene();
  scene["material"]["E"] = -3;
  write("scene.json", scene.dump());
  const CliRun run = incise("solve scene.json --out result.json");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.err, "incise: scene.json: material.E: must be positive (got -3)\n");
  EXPECT_FALSE(fs::exists(dir_ / "result.json"));
}

TEST_F(Cli, EmptySelectionUnknownKeyAndBadJsonAreReported) {
  json empty_selection = small_scene();
  empty_selection["constraints"][0]["where"]["box"] = json::parse("[[1, 1, 1], [2, 2, 2]]");
  write("a.json", empty_selection.dump());
  CliRun run = incise("solve a.json --out r.json");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.err, "incise: a.json: constraints[0].where.box: selects no node\n");

  json unknown = small_scene();
  unknown["solver"]["order"] = 2;
  write("b.json", unknown.dump());
  run = incise("solve b.json --out r.json");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.err,
            "incise: b.json: solver.order: unknown key (expected one of: integrator, dt, "
            "steps, tolerance, linear_solver, preconditioner)\n");

  write("c.json", "{\"mesh\": {\"box\": ");
  run = incise("solve c.json --out r.json");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.err.rfind("incise: c.json: malformed JSON: parse error at line 1", 0), 0u)
      << run.err;
  EXPECT_TRUE(one_line(run.err)) << run.err;

  run = incise("solve missing.json --out r.json");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.err, "incise: missing.json: cannot open file (No such file or directory)\n");
}

TEST_F(Cli, NonFiniteStateGivesExitCode1AndAResult) {
  json scene = small_scene();
  scene["solver"]["dt"] = 1e200;  // the first step overflows
  scene["solver"]["steps"] = 100000;
  write("scene.json", scene.dump());
  const CliRun run = incise("solve scene.json --out result.json");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_TRUE(one_line(run.err)) << run.err;
  EXPECT_EQ(run.err.rfind("incise: scene.json: not finite at step 1: ", 0), 0u) << run.err;
  const json result = json::parse(test::read_file(dir_ / "result.json"));
  EXPECT_EQ(result.at("finite"), false);
  EXPECT_LT(result.at("steps").get<int>(), 100000);
  EXPECT_EQ("incise: scene.json: " + result.at("status").get<std::string>() + "\n", run.err);
}

// The general runner (here linear FEM) stops a run that grows without bound before it overflows,
// and says so in the result and on stderr.
TEST_F(Cli, DivergedRunGivesExitCode1AndTheStatus) {
  json scene = small_scene();
  scene["material"]["model"] = "linear";
  scene["solver"]["dt"] = 0.05;
  scene["solver"]["steps"] = 100000;
  write("scene.json", scene.dump());
  const CliRun run = incise("solve scene.json --out result.json");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_TRUE(one_line(run.err)) << run.err;
  EXPECT_EQ(run.err.rfind("incise: scene.json: diverged at step ", 0), 0u) << run.err;
  const json result = json::parse(test::read_file(dir_ / "result.json"));
  EXPECT_EQ(result.at("finite"), false);
  EXPECT_LT(result.at("steps").get<int>(), 1000);
  EXPECT_EQ("incise: scene.json: " + result.at("status").get<std::string>() + "\n", run.err);
}

TEST_F(Cli, UsageErrorsGiveExitCode2AndAUsageLine) {
  for (const std::string arguments :
       {"", "frobnicate", "solve", "solve scene.json", "solve scene.json --out",
        "solve a.json b.json --out r.json", "solve scene.json --out r.json --fast"}) {
    const CliRun run = incise(arguments);
    EXPECT_EQ(run.exit_code, 2) << arguments;
    EXPECT_TRUE(one_line(run.err)) << arguments << ": " << run.err;
    EXPECT_NE(run.err.find("usage: incise solve SCENE.json --out RESULT.json"), std::string::npos)
        << arguments;
  }
}

TEST_F(Cli, HelpDescribesTheContractAndTheExample) {
  const CliRun run = incise("--help");
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_EQ(run.err, "");
  EXPECT_NE(run.out.find("incise solve SCENE.json --out RESULT.json"), std::string::npos);
  EXPECT_NE(run.out.find("sim/scenes/clamped_box.json"), std::string::npos);
  EXPECT_NE(run.out.find("sim/scenes/adaptive_box.json"), std::string::npos);
  EXPECT_NE(run.out.find("ramped"), std::string::npos);
}

TEST_F(Cli, UnwritableResultIsReported) {
  write("scene.json", small_scene().dump());
  const CliRun run = incise("solve scene.json --out no/such/dir/result.json");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.err, "incise: no/such/dir/result.json: cannot write the result\n");
}

// The scene file's keys through the real binary: a mesh from a gmsh file, a Neo-Hookean static
// solve to a tolerance, the final state written as .vtu, and a generated (CGAL) mesh.
TEST_F(Cli, MeshFilesModelsIntegratorsAndVtuOutput) {
  const TetMesh box = make_box_mesh(Vec3(0.02, 0.02, 0.02), Vec3i(2, 2, 2));
  write_msh(dir_ / "block.msh", box, MshVersion::k4_1);
  json scene = json::parse(R"({
    "mesh": {"file": "block.msh"},
    "material": {"model": "neohookean", "E": 3000, "nu": 0.3, "density": 1000},
    "constraints": [
      {"where": {"box": [[0, -1, -1], [0, 1, 1]]}, "fix": "x"},
      {"where": {"box": [[-1, 0, -1], [1, 0, 1]]}, "fix": "y"},
      {"where": {"box": [[-1, -1, 0], [1, 1, 0]]}, "fix": "z"},
      {"where": {"box": [[-1, -1, 0.02], [1, 1, 0.02]]}, "displace": [0, 0, -0.002], "axes": "z"}],
    "solver": {"integrator": "static", "steps": 2, "tolerance": 1e-10},
    "output": {"vtu": "final.vtu"}})");
  write("static.json", scene.dump());
  CliRun run = incise("solve static.json --out r.json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json result = json::parse(test::read_file(dir_ / "r.json"));
  EXPECT_EQ(result.at("tets"), box.num_tets());
  EXPECT_TRUE(result.at("solver").at("converged").get<bool>());
  EXPECT_LT(result.at("solver").at("relative_residual").get<double>(), 1e-10);
  // The top moved down by the prescribed 2 mm, exactly.
  double lowest_top = 1;
  for (std::size_t i = 0; i < result.at("rest").size(); ++i) {
    if (result["rest"][i][2].get<double>() > 0.02 - 1e-12) {
      lowest_top = std::min(lowest_top, result["displacement"][i][2].get<double>());
    }
  }
  EXPECT_DOUBLE_EQ(lowest_top, -0.002);
  const std::string vtu = test::read_file(dir_ / "final.vtu");
  EXPECT_NE(vtu.find("NumberOfCells=\"" + std::to_string(box.num_tets()) + "\""),
            std::string::npos);

  scene["mesh"] = json::parse(R"({"file": "missing.msh"})");
  write("missing.json", scene.dump());
  run = incise("solve missing.json --out r.json");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.err.rfind("incise: missing.json: mesh.file: ", 0), 0u) << run.err;

  json generated = json::parse(R"({
    "mesh": {"generate": {"shape": "sphere", "centre": [0, 0, 0], "radius": 0.02,
                          "cell_size": 0.008}},
    "material": {"model": "corotational", "E": 3000, "nu": 0.45, "density": 1000},
    "solver": {"integrator": "implicit_euler", "dt": 0.01, "steps": 3}})");
  write("sphere.json", generated.dump());
  run = incise("solve sphere.json --out s.json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json sphere = json::parse(test::read_file(dir_ / "s.json"));
  EXPECT_GT(sphere.at("tets").get<int>(), 20);
  // Every generated node lies within the sphere (up to the meshing tolerance).
  for (const auto& p : sphere.at("rest")) {
    EXPECT_LT(std::hypot(p[0].get<double>(), p[1].get<double>(), p[2].get<double>()), 0.0205);
  }
}

}  // namespace
}  // namespace incise::sim
