// Bad input to the grasper (sim/tools/grasper.h): std::invalid_argument with a message naming
// the call and the offending value, and the grasper unchanged.

#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sim/tools/grasper.h"

namespace incise::sim::tools {
namespace {

template <class Call>
void expect_invalid(Call&& call, const std::string& expected) {
  try {
    call();
    ADD_FAILURE() << "no exception; expected: " << expected;
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find(expected), std::string::npos)
        << "message: " << error.what() << "\nexpected to contain: " << expected;
  }
}

GraspSettings with(void (*change)(GraspSettings&)) {
  GraspSettings s;
  change(s);
  return s;
}

TEST(GraspInput, SettingsOutOfRange) {
  expect_invalid([] { Grasper g(with([](GraspSettings& s) { s.jaw_length = 0; })); },
                 "jaw_length must be finite and > 0, got 0");
  expect_invalid([] { Grasper g(with([](GraspSettings& s) { s.jaw_radius = -1; })); },
                 "jaw_radius must be finite and > 0, got -1");
  expect_invalid([] { Grasper g(with([](GraspSettings& s) { s.grab_margin = -0.5; })); },
                 "grab_margin must be finite and >= 0, got -0.5");
  expect_invalid(
      [] {
        Grasper g(with([](GraspSettings& s) { s.reach = std::numeric_limits<Real>::quiet_NaN(); }));
      },
      "reach must be finite and >= 0");
  expect_invalid([] { Grasper g(with([](GraspSettings& s) { s.close_angle = 4; })); },
                 "close_angle must be in [0, pi), got 4");
  expect_invalid(
      [] {
        Grasper g(with([](GraspSettings& s) {
          s.close_angle = 0.3;
          s.open_angle = 0.2;
        }));
      },
      "open_angle must be in [close_angle, pi), got 0.2");
  expect_invalid([] { Grasper g(with([](GraspSettings& s) { s.tear_force = 0; })); },
                 "tear_force must be > 0, got 0");
  Grasper g;
  expect_invalid([&] { g.set_tear_force(-2); }, "set_tear_force: tear_force must be > 0, got -2");
  EXPECT_EQ(g.settings().tear_force, GraspSettings{}.tear_force);
}

TEST(GraspInput, BadPoseLeavesTheGrasperUnchanged) {
  Grasper g;
  JawPose pose;
  pose.opening_angle = 0;
  g.set_jaws(pose);
  ASSERT_EQ(g.phase(), GraspPhase::closing);
  const collide::JawPair jaws = g.jaws();
  JawPose bad = pose;
  bad.direction = Vec3::Zero();
  expect_invalid([&] { g.set_jaws(bad); }, "direction must be a finite non-zero vector");
  bad = pose;
  bad.opening_angle = -0.1;
  expect_invalid([&] { g.set_jaws(bad); }, "opening_angle must be in [0, pi)");
  EXPECT_EQ(g.phase(), GraspPhase::closing);
  EXPECT_EQ(g.jaws().jaws[0].b, jaws.jaws[0].b);
}

TEST(GraspInput, ArraysOfTheWrongSizeOrIndicesOutOfRange) {
  Grasper g;
  g.set_jaws(JawPose{});
  const Points rest = Points::Zero(4, 3);
  const VecX inverse_masses = VecX::Ones(4);
  const std::vector<int> candidates{0, 1, 2, 3};
  expect_invalid([&] { g.grab(rest, Points::Zero(3, 3), inverse_masses, candidates); },
                 "Grasper::grab: rest, x and inverse_masses must have the same number of rows, "
                 "got 4, 3 and 4");
  const std::vector<int> outside{0, 4};
  expect_invalid([&] { g.grab(rest, rest, inverse_masses, outside); },
                 "Grasper::grab: candidate 1 is vertex 4, outside [0, 4)");
  expect_invalid([&] { g.refine_request(rest, rest, VecX::Ones(5), candidates); },
                 "Grasper::refine_request: rest, x and inverse_masses must have the same number");
  EXPECT_EQ(g.phase(), GraspPhase::closing);

  // Holding vertex 3 (all four sit at the pivot, inside the jaws).
  ASSERT_EQ(g.grab(rest, rest, inverse_masses, candidates), 4);
  expect_invalid([&] { g.measure(Points::Zero(3, 3)); },
                 "Grasper::measure: internal_forces has 3 rows, the grasper holds vertex 3");
  Prescribed small{AxisMask::Zero(3, 3), Points::Zero(4, 3)};
  expect_invalid([&] { g.prescribe(small); },
                 "Grasper::prescribe: mask and position need a row for vertex 3, got 3 and 4");
  Points x = Points::Zero(4, 3);
  Points v = Points::Zero(2, 3);
  expect_invalid([&] { g.hold(0.001, x, v); },
                 "Grasper::hold: x and v need a row for vertex 3, got 4 and 2");
  expect_invalid([&] { g.hold(0, x, x); }, "Grasper::hold: dt must be finite and > 0, got 0");
  const std::vector<int> short_map{0, 1};
  expect_invalid([&] { g.remap(short_map); },
                 "Grasper::remap: held vertex 2 is outside old_to_new (2 entries)");
  const std::vector<int> merging{0, 1, 1, 2};
  expect_invalid([&] { g.remap(merging); }, "Grasper::remap: two held vertices map to vertex 1");
  EXPECT_EQ(g.grabbed(), candidates);
  // Outside closing, grab is a logic error, not bad input.
  EXPECT_THROW(g.grab(rest, rest, inverse_masses, candidates), std::logic_error);
}

TEST(GraspInput, FixedAndDeadVerticesAreNeverGrabbed) {
  Grasper g;
  g.set_jaws(JawPose{});
  const Points rest = Points::Zero(3, 3);
  VecX inverse_masses(3);
  inverse_masses << 0, 1, 0;
  const std::vector<int> candidates{0, 1, 2, 1};
  EXPECT_EQ(g.grab(rest, rest, inverse_masses, candidates), 1);
  EXPECT_EQ(g.grabbed(), std::vector<int>{1});
}

}  // namespace
}  // namespace incise::sim::tools
