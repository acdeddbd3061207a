#include "sim/scene/scene_validation.h"

#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <string>

namespace incise::sim {
namespace {

Scene valid_scene() {
  Scene scene;
  scene.mesh.box = {Vec3(0.04, 0.04, 0.04), Vec3i(2, 2, 2)};
  scene.material = {MaterialModel::mass_spring, 3000, 0.45, 1000, 0.1};
  scene.constraints = {
      {{Box3(Vec3(0, 0, 0), Vec3(0.04, 0.04, 0))}, {true, true, true}, Vec3::Zero()}};
  scene.loads = {{{Box3(Vec3(0, 0, 0.04), Vec3(0.04, 0.04, 0.04))}, Vec3(0, 0, -1)}};
  scene.gravity = Vec3(0, 0, -9.81);
  scene.solver = {Integrator::symplectic_euler, 1e-4, 100};
  return scene;
}

// The message validate_scene gives after edit is applied to a valid scene.
std::string error_after(const std::function<void(Scene&)>& edit) {
  Scene scene = valid_scene();
  edit(scene);
  try {
    validate_scene(scene);
  } catch (const SceneError& error) {
    return error.what();
  }
  return "no error";
}

TEST(ValidateScene, AcceptsAValidScene) {
  EXPECT_NO_THROW(validate_scene(valid_scene()));
}

TEST(ValidateScene, NamesTheKeyAndTheProblem) {
  EXPECT_EQ(error_after([](Scene& s) { s.material.youngs_modulus = -3; }),
            "material.E: must be positive (got -3)");
  EXPECT_EQ(error_after([](Scene& s) { s.material.density = 0; }),
            "material.density: must be positive (got 0)");
  EXPECT_EQ(error_after([](Scene& s) { s.material.poisson_ratio = 0.5; }),
            "material.nu: must be in (-1, 0.5) (got 0.5)");
  EXPECT_EQ(error_after([](Scene& s) { s.material.poisson_ratio = -1; }),
            "material.nu: must be in (-1, 0.5) (got -1)");
  EXPECT_EQ(error_after([](Scene& s) { s.material.damping = 1.5; }),
            "material.damping: must be in [0, 1] (got 1.5)");
  EXPECT_EQ(error_after([](Scene& s) { s.mesh.box.size.y() = 0; }),
            "mesh.box.size[1]: must be positive (got 0)");
  EXPECT_EQ(error_after([](Scene& s) { s.mesh.box.cells.z() = 0; }),
            "mesh.box.cells[2]: must be at least 1 (got 0)");
  EXPECT_EQ(error_after([](Scene& s) { s.mesh.box.cells = Vec3i(1000, 1000, 2); }),
            "mesh.box.cells: at most 1000000 cells in all (got 2000000)");
  EXPECT_EQ(error_after([](Scene& s) { s.solver.dt = 0; }), "solver.dt: must be positive (got 0)");
  EXPECT_EQ(error_after([](Scene& s) { s.solver.steps = 0; }),
            "solver.steps: must be at least 1 (got 0)");
  EXPECT_EQ(error_after([](Scene& s) {
              s.constraints[0].where.box = Box3(Vec3(0, 1, 0), Vec3(1, 0.5, 1));
            }),
            "constraints[0].where.box: min corner exceeds max corner in y (1 > 0.5)");
  EXPECT_EQ(error_after([](Scene& s) {
              s.constraints[0].axes = {false, false, false};
            }),
            "constraints[0]: constrains no axis");
  EXPECT_EQ(
      error_after([](Scene& s) { s.loads[0].force.x() = std::numeric_limits<Real>::infinity(); }),
      "loads[0].force[0]: must be finite (got inf)");
  EXPECT_EQ(error_after([](Scene& s) { s.gravity.z() = std::numeric_limits<Real>::quiet_NaN(); }),
            "gravity[2]: must be finite (got nan)");
}

TEST(ValidateScene, ToolAndViewAreCheckedWhenPresent) {
  constexpr Real kNaN = std::numeric_limits<Real>::quiet_NaN();
  const auto with_tool = [](const std::function<void(SphereTool&)>& edit) {
    return [edit](Scene& s) {
      s.tool = SphereTool{};
      edit(*s.tool);
    };
  };
  const auto with_view = [](const std::function<void(ViewSpec&)>& edit) {
    return [edit](Scene& s) {
      s.view = ViewSpec{Vec3(0, -1, 1), Vec3::Zero(), Vec3::UnitZ(), 45};
      edit(*s.view);
    };
  };
  EXPECT_EQ(error_after(with_tool([](SphereTool&) {})), "no error");
  EXPECT_EQ(error_after(with_view([](ViewSpec&) {})), "no error");
  EXPECT_EQ(error_after(with_tool([](SphereTool& t) { t.radius = kNaN; })),
            "tool.radius: must be finite (got nan)");
  EXPECT_EQ(error_after(with_tool([](SphereTool& t) { t.stiffness = 0; })),
            "tool.stiffness: must be positive (got 0)");
  EXPECT_EQ(error_after(with_tool([](SphereTool& t) { t.damping = kNaN; })),
            "tool.damping: must be finite (got nan)");
  EXPECT_EQ(error_after(with_tool([](SphereTool& t) { t.damping = -1; })),
            "tool.damping: must not be negative (got -1)");
  EXPECT_EQ(error_after(with_view([](ViewSpec& v) { v.eye.y() = kNaN; })),
            "view.eye[1]: must be finite (got nan)");
  EXPECT_EQ(error_after(with_view([](ViewSpec& v) { v.target = v.eye; })),
            "view.target: must differ from view.eye");
  EXPECT_EQ(error_after(with_view([](ViewSpec& v) { v.up = Vec3(0, 2, -2); })),
            "view.up: must not be zero or parallel to target - eye");
  EXPECT_EQ(error_after(with_view([](ViewSpec& v) { v.fov_y_deg = -10; })),
            "view.fov_y_deg: must be in (0, 180) (got -10)");
}

TEST(FormatNumber, ShortestRoundTrip) {
  EXPECT_EQ(format_number(-3), "-3");
  EXPECT_EQ(format_number(0.1), "0.1");
  EXPECT_EQ(format_number(2.5e-7), "2.5e-07");
}

}  // namespace
}  // namespace incise::sim
