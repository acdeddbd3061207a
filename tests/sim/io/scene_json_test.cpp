#include "sim/io/scene_json.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "sim/io/json_object_reader.h"
#include "sim/scene/scene_error.h"
#include "tests/support/temp_dir.h"

namespace incise::sim {
namespace {

using nlohmann::json;

json good_scene() {
  return json::parse(R"({
    "mesh": {"box": {"size": [0.1, 0.02, 0.03], "cells": [10, 2, 3]}},
    "material": {"model": "mss", "E": 3000, "nu": 0.45, "density": 1000, "damping": 0.2},
    "constraints": [
      {"where": {"box": [[0, 0, 0], [0, 0.02, 0.03]]}, "fix": "zx"},
      {"where": {"box": [[0.1, 0, 0], [0.1, 0.02, 0.03]]}, "displace": [0.01, 0, 0], "axes": "x"},
      {"where": {"box": [[0.05, 0, 0], [0.05, 0.02, 0.03]]}, "displace": [0, 0.001, 0]}
    ],
    "loads": [{"where": {"box": [[0, 0, 0.03], [0.1, 0.02, 0.03]]}, "force": [0, 0, -0.5]}],
    "gravity": [0, 0, -9.81],
    "solver": {"integrator": "symplectic_euler", "dt": 1e-4, "steps": 10000},
    "tool": {"radius": 0.004, "stiffness": 250, "damping": 0.01},
    "view": {"eye": [0.05, -0.1, 0.1], "target": [0.05, 0.01, 0.015], "up": [0, 0, 1],
             "fov_y_deg": 35}
  })");
}

TEST(ParseScene, ReadsEveryMember) {
  const Scene scene = parse_scene(good_scene());
  EXPECT_EQ(scene.material.volume_stiffness, 0);
  EXPECT_EQ(scene.mesh.box.size, Vec3(0.1, 0.02, 0.03));
  EXPECT_EQ(scene.mesh.box.cells, Vec3i(10, 2, 3));
  EXPECT_EQ(scene.material.model, MaterialModel::mass_spring);
  EXPECT_EQ(scene.material.youngs_modulus, 3000);
  EXPECT_EQ(scene.material.poisson_ratio, 0.45);
  EXPECT_EQ(scene.material.density, 1000);
  EXPECT_EQ(scene.material.damping, 0.2);
  ASSERT_EQ(scene.constraints.size(), 3u);
  EXPECT_EQ(scene.constraints[0].where.box.min(), Vec3(0, 0, 0));
  EXPECT_EQ(scene.constraints[0].where.box.max(), Vec3(0, 0.02, 0.03));
  EXPECT_EQ(scene.constraints[0].axes, (Axes{true, false, true}));
  EXPECT_EQ(scene.constraints[0].displacement, Vec3::Zero());
  EXPECT_EQ(scene.constraints[1].axes, (Axes{true, false, false}));
  EXPECT_EQ(scene.constraints[1].displacement, Vec3(0.01, 0, 0));
  EXPECT_EQ(scene.constraints[2].axes, (Axes{true, true, true}));  // default "xyz"
  ASSERT_EQ(scene.loads.size(), 1u);
  EXPECT_EQ(scene.loads[0].force, Vec3(0, 0, -0.5));
  EXPECT_EQ(scene.gravity, Vec3(0, 0, -9.81));
  EXPECT_EQ(scene.solver.integrator, Integrator::symplectic_euler);
  EXPECT_EQ(scene.solver.dt, 1e-4);
  EXPECT_EQ(scene.solver.steps, 10000);
  ASSERT_TRUE(scene.tool.has_value());
  EXPECT_EQ(scene.tool->radius, 0.004);
  EXPECT_EQ(scene.tool->stiffness, 250);
  EXPECT_EQ(scene.tool->damping, 0.01);
  ASSERT_TRUE(scene.view.has_value());
  EXPECT_EQ(scene.view->eye, Vec3(0.05, -0.1, 0.1));
  EXPECT_EQ(scene.view->target, Vec3(0.05, 0.01, 0.015));
  EXPECT_EQ(scene.view->up, Vec3(0, 0, 1));
  EXPECT_EQ(scene.view->fov_y_deg, 35);
}

TEST(ParseScene, ToolAndViewMembersHaveDefaults) {
  json value = good_scene();
  value["tool"] = json::object();
  value["view"].erase("up");
  value["view"].erase("fov_y_deg");
  const Scene scene = parse_scene(value);
  ASSERT_TRUE(scene.tool.has_value());
  EXPECT_EQ(scene.tool->radius, SphereTool{}.radius);
  EXPECT_EQ(scene.tool->stiffness, SphereTool{}.stiffness);
  EXPECT_EQ(scene.tool->damping, SphereTool{}.damping);
  EXPECT_EQ(scene.view->up, Vec3::UnitZ());
  EXPECT_EQ(scene.view->fov_y_deg, 45);
}

TEST(ParseScene, OptionalMembersHaveDefaults) {
  json value = good_scene();
  value.erase("constraints");
  value.erase("loads");
  value.erase("gravity");
  value["material"].erase("damping");
  value["solver"]["steps"] = 1e4;  // an integral float counts as an integer
  value.erase("tool");
  value.erase("view");
  const Scene scene = parse_scene(value);
  EXPECT_FALSE(scene.tool.has_value());
  EXPECT_FALSE(scene.view.has_value());
  EXPECT_TRUE(scene.constraints.empty());
  EXPECT_TRUE(scene.loads.empty());
  EXPECT_EQ(scene.gravity, Vec3::Zero());
  EXPECT_EQ(scene.material.damping, 0.1);
  EXPECT_EQ(scene.solver.steps, 10000);
}

struct BadCase {
  const char* pointer;  // JSON pointer of the member to change
  const char* value;    // its new value as JSON text, or nullptr to remove it
  const char* message;  // SceneError::what()
};

TEST(ParseScene, VolumeStiffnessBelongsToTheMassSpringModel) {
  json value = good_scene();
  value["material"]["volume_stiffness"] = 2.5;
  EXPECT_EQ(parse_scene(value).material.volume_stiffness, 2.5);
  value["material"]["model"] = "linear";
  try {
    parse_scene(value);
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    EXPECT_STREQ(e.what(),
                 "material.volume_stiffness: only the mss model has a volume term (the FEM "
                 "models' volume response comes from nu)");
  }
}

// Changes the member at bad.pointer of value (or removes it) and expects exactly bad.message.
void expect_scene_error(json value, const BadCase& bad) {
  const json::json_pointer pointer(bad.pointer);
  if (bad.value == nullptr) {
    value[pointer.parent_pointer()].erase(pointer.back());
  } else {
    value[pointer] = json::parse(bad.value);
  }
  try {
    parse_scene(value);
    FAIL() << "no error";
  } catch (const SceneError& error) {
    EXPECT_EQ(std::string(error.what()), bad.message);
  }
}

class ParseSceneErrors : public ::testing::TestWithParam<BadCase> {};

TEST_P(ParseSceneErrors, NameTheKeyAndTheProblem) {
  expect_scene_error(good_scene(), GetParam());
}

INSTANTIATE_TEST_SUITE_P(
    Cases, ParseSceneErrors,
    ::testing::Values(
        BadCase{"/material/E", "-3", "material.E: must be positive (got -3)"},
        BadCase{"/material/E", "\"stiff\"", "material.E: must be a number (got \"stiff\")"},
        BadCase{"/material/E", "true", "material.E: must be a number (got true)"},
        BadCase{"/material/E", nullptr, "material.E: is required"},
        BadCase{"/material/density", "0", "material.density: must be positive (got 0)"},
        BadCase{"/material/nu", "0.5", "material.nu: must be in (-1, 0.5) (got 0.5)"},
        BadCase{"/material/nu", "-1.2", "material.nu: must be in (-1, 0.5) (got -1.2)"},
        BadCase{"/material/model", "\"fem\"",
                "material.model: unknown model \"fem\" (expected: mss, linear, corotational, "
                "corotational_polar, corotational_nodal_pressure, stvk, neohookean)"},
        BadCase{"/material/youngs", "1",
                "material.youngs: unknown key (expected one of: model, E, nu, density, "
                "damping, volume_stiffness)"},
        BadCase{"/material/volume_stiffness", "-1",
                "material.volume_stiffness: must not be negative (got -1)"},
        BadCase{"/material", "[]", "material: must be an object (got [])"},
        BadCase{"/mesh", nullptr, "mesh: is required"},
        BadCase{"/material", nullptr, "material: is required"},
        BadCase{"/solver", nullptr, "solver: is required"},
        BadCase{"/mesh/box/size", "[0.1, 0.02]",
                "mesh.box.size: must be an array of 3 numbers (got [0.1,0.02])"},
        BadCase{"/mesh/box/size/1", "-0.02", "mesh.box.size[1]: must be positive (got -0.02)"},
        BadCase{"/mesh/box/cells/2", "2.5", "mesh.box.cells[2]: must be an integer (got 2.5)"},
        BadCase{"/mesh/box/cells/0", "0", "mesh.box.cells[0]: must be at least 1 (got 0)"},
        BadCase{"/mesh/file", "\"liver.msh\"",
                "mesh: has more than one of \"box\", \"file\", \"generate\", \"segmentation\""},
        BadCase{"/mesh/box", nullptr,
                "mesh: needs one of \"box\", \"file\", \"generate\", \"segmentation\""},
        BadCase{"/solver/tolerance", "2", "solver.tolerance: must be in (0, 1) (got 2)"},
        BadCase{"/materials", "{\"x\": {}}", "materials.x: a label must be a non-negative integer"},
        BadCase{"/materials", "{\"2\": {\"E\": 1, \"nu\": 0.5, \"density\": 1}}",
                "materials.2.nu: must be in (-1, 0.5) (got 0.5)"},
        BadCase{"/constraints/0/fix", "\"xw\"",
                "constraints[0].fix: must be a non-empty subset of \"xyz\" (got \"xw\")"},
        BadCase{"/constraints/0/fix", "\"xx\"",
                "constraints[0].fix: must be a non-empty subset of \"xyz\" (got \"xx\")"},
        BadCase{"/constraints/0/fix", "\"\"",
                "constraints[0].fix: must be a non-empty subset of \"xyz\" (got \"\")"},
        BadCase{"/constraints/0/fix", nullptr, "constraints[0]: needs \"fix\" or \"displace\""},
        BadCase{"/constraints/0/displace", "[1, 0, 0]",
                "constraints[0]: has both \"fix\" and \"displace\" (give one)"},
        BadCase{"/constraints/0/axes", "\"x\"",
                "constraints[0].axes: belongs to \"displace\" (\"fix\" names its axes)"},
        BadCase{"/constraints/1/axes", "\"q\"",
                "constraints[1].axes: must be a non-empty subset of \"xyz\" (got \"q\")"},
        BadCase{"/constraints/1/displace/2", "null",
                "constraints[1].displace[2]: must be a number (got null)"},
        BadCase{"/constraints/1/where/box", "[[0, 0, 0]]",
                "constraints[1].where.box: must be [[x0, y0, z0], [x1, y1, z1]] (got "
                "[[0,0,0]])"},
        BadCase{"/constraints/1/where/box/1/0", "-1",
                "constraints[1].where.box: min corner exceeds max corner in x (0.1 > -1)"},
        BadCase{"/constraints/1/where/sphere", "1",
                "constraints[1].where.sphere: unknown key (expected one of: box)"},
        BadCase{"/constraints", "{}", "constraints: must be an array (got {})"},
        BadCase{"/loads/0/force", nullptr, "loads[0].force: is required"},
        BadCase{"/loads/0/where/box/0/2", "\"top\"",
                "loads[0].where.box[0][2]: must be a number (got \"top\")"},
        BadCase{"/gravity", "[0, 0]", "gravity: must be an array of 3 numbers (got [0,0])"},
        BadCase{"/solver/integrator", "\"rk4\"",
                "solver.integrator: unknown integrator \"rk4\" (expected: symplectic_euler, "
                "central_difference, adaptive_explicit, implicit_euler, static)"},
        BadCase{"/solver/dt", "0", "solver.dt: must be positive (got 0)"},
        BadCase{"/solver/steps", "-5", "solver.steps: must be at least 1 (got -5)"},
        BadCase{"/solver/steps", "\"many\"", "solver.steps: must be an integer (got \"many\")"},
        BadCase{"/solver/order", "2",
                "solver.order: unknown key (expected one of: integrator, dt, steps, tolerance, "
                "linear_solver, preconditioner)"},
        BadCase{"/solver/linear_solver", "\"gauss\"",
                "solver.linear_solver: unknown linear solver \"gauss\" (expected: cg, "
                "assembled_cg, ldlt)"},
        BadCase{"/solver/preconditioner", "\"ilu\"",
                "solver.preconditioner: unknown preconditioner \"ilu\" (expected: jacobi, "
                "block_jacobi, incomplete_cholesky)"},
        BadCase{"/solver/preconditioner", "\"incomplete_cholesky\"",
                "solver.preconditioner: incomplete_cholesky needs \"linear_solver\": "
                "\"assembled_cg\""},
        BadCase{"/tool", "0.005", "tool: must be an object (got 0.005)"},
        BadCase{"/tool/radius", "0", "tool.radius: must be positive (got 0)"},
        BadCase{"/tool/radius", "\"big\"", "tool.radius: must be a number (got \"big\")"},
        BadCase{"/tool/stiffness", "-300", "tool.stiffness: must be positive (got -300)"},
        BadCase{"/tool/damping", "-0.1", "tool.damping: must not be negative (got -0.1)"},
        BadCase{"/tool/shape", "\"sphere\"",
                "tool.shape: unknown key (expected one of: radius, stiffness, damping)"},
        BadCase{"/view/eye", nullptr, "view.eye: is required"},
        BadCase{"/view/target", "[0, 0]", "view.target: must be an array of 3 numbers (got [0,0])"},
        BadCase{"/view/target", "[0.05, -0.1, 0.1]", "view.target: must differ from view.eye"},
        BadCase{"/view/up", "[0, 0, 0]", "view.up: must not be zero or parallel to target - eye"},
        BadCase{"/view/up", "[0, -0.11, 0.085]",
                "view.up: must not be zero or parallel to target - eye"},
        BadCase{"/view/fov_y_deg", "180", "view.fov_y_deg: must be in (0, 180) (got 180)"},
        BadCase{"/view/fov_y_deg", "0", "view.fov_y_deg: must be in (0, 180) (got 0)"},
        BadCase{"/view/near", "0.01",
                "view.near: unknown key (expected one of: eye, target, up, fov_y_deg)"},
        BadCase{"/extra", "1",
                "extra: unknown key (expected one of: mesh, material, materials, constraints, "
                "loads, gravity, solver, tool, view, output, adaptivity)"}));

// A scene with "adaptivity": clamped at its base ("fix": "xyz"), symplectic Euler.
json adaptive_scene() {
  return json::parse(R"({
    "mesh": {"box": {"size": [0.02, 0.02, 0.04], "cells": [2, 2, 4]}},
    "material": {"model": "mss", "E": 3000, "nu": 0.45, "density": 1000},
    "constraints": [{"where": {"box": [[0, 0, 0], [0.02, 0.02, 0]]}, "fix": "xyz"}],
    "gravity": [0, 0, -9.81],
    "solver": {"integrator": "symplectic_euler", "dt": 1e-4, "steps": 100},
    "adaptivity": {"l_min": 0.002, "fine_size": 0.004, "quality": 1.8, "every": 20,
                   "strain": {"on": 0.05, "off": 0.03},
                   "curvature": {"on_degrees": 20, "off_degrees": 10}, "keep_margin": 0.001}
  })");
}

TEST(ParseScene, ReadsAdaptivity) {
  EXPECT_FALSE(parse_scene(good_scene()).adaptivity.has_value());
  const Scene scene = parse_scene(adaptive_scene());
  ASSERT_TRUE(scene.adaptivity.has_value());
  const AdaptivitySpec& a = *scene.adaptivity;
  EXPECT_EQ(a.l_min, 0.002);
  EXPECT_EQ(a.dt_min, 0);
  EXPECT_EQ(a.fine_size, 0.004);
  EXPECT_EQ(a.quality, 1.8);
  EXPECT_EQ(a.every, 20);
  EXPECT_TRUE(a.strain);
  EXPECT_EQ(a.strain_on, 0.05);
  EXPECT_EQ(a.strain_off, 0.03);
  EXPECT_TRUE(a.curvature);
  EXPECT_EQ(a.bend_on_degrees, 20);
  EXPECT_EQ(a.bend_off_degrees, 10);
  EXPECT_EQ(a.keep_margin, 0.001);

  json value = adaptive_scene();
  json& adaptivity = value["adaptivity"];
  adaptivity.erase("l_min");
  adaptivity["dt_min"] = 2e-4;
  for (const char* key : {"quality", "every", "curvature", "keep_margin"})
    adaptivity.erase(key);
  const AdaptivitySpec defaults = *parse_scene(value).adaptivity;
  EXPECT_EQ(defaults.l_min, 0);
  EXPECT_EQ(defaults.dt_min, 2e-4);
  EXPECT_EQ(defaults.quality, 2.0);
  EXPECT_EQ(defaults.every, 10);
  EXPECT_FALSE(defaults.curvature);
  EXPECT_FALSE(defaults.keep_margin.has_value());
}

class ParseAdaptivityErrors : public ::testing::TestWithParam<BadCase> {};

TEST_P(ParseAdaptivityErrors, NameTheKeyAndTheProblem) {
  expect_scene_error(adaptive_scene(), GetParam());
}

INSTANTIATE_TEST_SUITE_P(
    Cases, ParseAdaptivityErrors,
    ::testing::Values(
        BadCase{"/adaptivity", "3", "adaptivity: must be an object (got 3)"},
        BadCase{"/adaptivity/l_min", nullptr, "adaptivity: needs \"l_min\" or \"dt_min\""},
        BadCase{"/adaptivity/dt_min", "1e-4",
                "adaptivity: has both \"l_min\" and \"dt_min\" (give one)"},
        BadCase{"/adaptivity/l_min", "0", "adaptivity.l_min: must be positive (got 0)"},
        BadCase{"/adaptivity/l_min", "-0.002", "adaptivity.l_min: must be positive (got -0.002)"},
        BadCase{"/adaptivity/fine_size", "0", "adaptivity.fine_size: must be positive (got 0)"},
        BadCase{"/adaptivity/fine_size", nullptr, "adaptivity.fine_size: is required"},
        BadCase{"/adaptivity/quality", "1", "adaptivity.quality: must be above 1 (got 1)"},
        BadCase{"/adaptivity/every", "0", "adaptivity.every: must be at least 1 (got 0)"},
        BadCase{"/adaptivity/every", "2.5", "adaptivity.every: must be an integer (got 2.5)"},
        BadCase{"/adaptivity/strain/off", "0.05",
                "adaptivity.strain: off must be below on (got off 0.05, on 0.05)"},
        BadCase{"/adaptivity/strain/off", "-0.01",
                "adaptivity.strain.off: must be positive (got -0.01)"},
        BadCase{"/adaptivity/strain/on", nullptr, "adaptivity.strain.on: is required"},
        BadCase{"/adaptivity/strain/level", "1",
                "adaptivity.strain.level: unknown key (expected one of: on, off)"},
        BadCase{"/adaptivity/curvature/off_degrees", "30",
                "adaptivity.curvature: off_degrees must be below on_degrees (got off 30, on 20)"},
        BadCase{"/adaptivity/curvature/on_degrees", "200",
                "adaptivity.curvature.on_degrees: must be at most 180 (got 200)"},
        BadCase{"/adaptivity/keep_margin", "-1",
                "adaptivity.keep_margin: must not be negative (got -1)"},
        BadCase{"/adaptivity/contact", "{}",
                "adaptivity.contact: unknown key (expected one of: l_min, dt_min, fine_size, "
                "quality, every, strain, curvature, keep_margin)"},
        BadCase{"/adaptivity", R"({"l_min": 0.002, "fine_size": 0.004})",
                "adaptivity: needs at least one criterion: \"strain\" or \"curvature\""},
        BadCase{"/solver/integrator", "\"implicit_euler\"",
                "adaptivity: needs solver.integrator \"symplectic_euler\" (got "
                "\"implicit_euler\")"},
        BadCase{"/constraints/0/fix", "\"z\"",
                "constraints[0]: with adaptivity a constraint must be \"fix\": \"xyz\" (this one "
                "frees an axis)"},
        BadCase{"/constraints/0",
                R"({"where": {"box": [[0, 0, 0], [0.02, 0.02, 0]]}, "displace": [0, 0, 0.001]})",
                "constraints[0]: with adaptivity a constraint must be \"fix\": \"xyz\" (this one "
                "displaces)"},
        // dt_min = 0.5 * 0.0005 / c with c = 3.373 m/s (E 3 kPa, nu 0.45, 1000 kg/m^3).
        BadCase{"/adaptivity/l_min", "0.0005",
                "adaptivity.l_min: refined tets are stable down to dt_min = 7.411089152360968e-05 "
                "s only, below solver.dt = 1e-04 s (give a larger l_min or a smaller dt)"},
        BadCase{"/adaptivity", R"({"dt_min": 5e-5, "fine_size": 0.004, "strain": {"on": 0.1,
                "off": 0.05}})",
                "adaptivity.dt_min: refined tets are stable down to dt_min = 5e-05 s only, below "
                "solver.dt = 1e-04 s (give a larger dt_min or a smaller dt)"}));

// Found by the fuzzing (a key "\u0000" made what() end at its first byte): every key a message
// names is readable, whatever bytes it holds.
TEST(ParseSceneText, AnUnknownKeyOfAnyBytesIsNamedReadably) {
  EXPECT_EQ(member_path("", "material"), "material");
  EXPECT_EQ(member_path("material", "E"), "material.E");
  EXPECT_EQ(member_path("", std::string_view("\0", 1)), "\"\\u0000\"");
  EXPECT_EQ(member_path("a", "x y"), "a.\"x y\"");
  EXPECT_EQ(member_path("a", "\xff"), "a.\"\xef\xbf\xbd\"");  // U+FFFD for the stray byte
  try {
    parse_scene_text(R"({"mesh": {"box": {"size": [1, 1, 1], "cells": [1, 1, 1]}}, "\u0000": 1})");
    FAIL() << "an unknown key was accepted";
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\0'), std::string::npos);
    EXPECT_EQ(what.rfind("\"\\u0000\": unknown key", 0), 0u) << what;
  }
}

TEST(ParseSceneText, MalformedJsonSaysWhere) {
  try {
    parse_scene_text("{\"mesh\": ");
    FAIL() << "no error";
  } catch (const SceneError& error) {
    EXPECT_EQ(error.path(), "");
    const std::string what = error.what();
    EXPECT_EQ(what.rfind("malformed JSON: parse error at line 1, column 10", 0), 0u) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos);
  }
  try {
    parse_scene_text("[1, 2]");
    FAIL() << "no error";
  } catch (const SceneError& error) {
    EXPECT_EQ(std::string(error.what()), "the scene must be a JSON object (got [1,2])");
  }
}

TEST(ReadSceneFile, ReadsAFileAndReportsAMissingOne) {
  const incise::test::TempDir dir{"incise-scene-json"};
  const auto path = dir.path() / "scene.json";
  std::ofstream(path) << good_scene().dump();
  EXPECT_EQ(read_scene_file(path).mesh.box.cells, Vec3i(10, 2, 3));
  std::filesystem::remove(path);
  try {
    read_scene_file(path);
    FAIL() << "no error";
  } catch (const SceneError& error) {
    EXPECT_EQ(std::string(error.what()), "cannot open file (No such file or directory)");
  }
}

TEST(ReadSceneFile, TheExampleScenesAreValid) {
  EXPECT_NO_THROW(read_scene_file(INCISE_SCENES_DIR "/clamped_box.json"));
  EXPECT_TRUE(read_scene_file(INCISE_SCENES_DIR "/adaptive_box.json").adaptivity.has_value());
  const Scene palpation = read_scene_file(INCISE_SCENES_DIR "/palpation.json");
  EXPECT_TRUE(palpation.tool.has_value());
  EXPECT_TRUE(palpation.view.has_value());
}

}  // namespace
}  // namespace incise::sim
