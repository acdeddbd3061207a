// The grasper's tear rule (sim/tools/grasper.h): a clamped block pulled slowly by the jaws lets go
// when the pull crosses the tissue's tear force. Checked against the threshold (the overshoot is
// one step's growth of the force) and against an independent static solve of the same stretch
// (the grabbed vertices held where they were at the release), for the mass-spring system of seed
// 000 and corotational FEM.

#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "grasp_fixtures.h"
#include "sim/solve/static_solver.h"

namespace incise::sim::tools {
namespace {

using testing::GraspedBlock;

class GraspRelease : public ::testing::TestWithParam<MaterialModel> {};

TEST_P(GraspRelease, TearsAtTheThresholdForceOfTheStaticStretch) {
  // A 2 x 2 x 4 cm block on 5 mm cells, base clamped, grabbed at the middle of its top face.
  GraspedBlock block(GetParam(), Vec3(0.02, 0.02, 0.04), Vec3i(4, 4, 8), true);
  GraspSettings settings;
  settings.jaw_radius = 0.003;
  settings.grab_margin = 0.0025;  // 5.5 mm: the centre node and its four neighbours at 5 mm
  settings.tear_force = 0.05;
  Grasper grasper(settings);
  const Vec3 start(0.01, 0.01, 0.04 + settings.jaw_length);  // tips on the top face

  // Pull up at 2 mm/s (quasi-static: the block's lowest period is about 0.1 s, and the ramp
  // leaves the damping force a fraction of a percent of the elastic one).
  constexpr Real kSpeed = 0.002;  // [m/s]
  const int max_steps = static_cast<int>(std::ceil(5.0 / block.dt));
  std::vector<int> held;
  std::optional<ReleaseEvent> event;
  int step = 0;
  for (; step < max_steps && !event; ++step) {
    const Vec3 pivot = start + Vec3(0, 0, kSpeed * step * block.dt);
    event = block.step(grasper, testing::downward_jaws(pivot, 0));
    if (step == 0) {
      held = grasper.grabbed();
      ASSERT_EQ(held.size(), 5u);
    }
  }
  ASSERT_TRUE(event.has_value()) << "no release within " << max_steps << " steps";
  EXPECT_EQ(event->reason, ReleaseReason::torn);
  EXPECT_EQ(event->released_vertices, 5);
  EXPECT_EQ(grasper.phase(), GraspPhase::closed_empty);
  EXPECT_TRUE(grasper.grabbed().empty());

  // The force at release has just crossed the threshold.
  const Real released = event->pull.norm();
  EXPECT_GT(released, settings.tear_force);
  EXPECT_LT(released, 1.05 * settings.tear_force);
  // The pull is upward (the tissue is stretched towards the jaws).
  EXPECT_GT(event->pull.z(), 0.9 * released);

  // Independently: the static equilibrium with the base clamped and the grabbed vertices held at
  // their positions at the release.
  const Points& x_release = block.start_x;
  Prescribed fixed;
  fixed.mask = AxisMask::Zero(block.mesh.num_nodes(), 3);
  fixed.position = block.mesh.rest;
  for (int i = 0; i < block.mesh.num_nodes(); ++i) {
    if (block.mesh.rest(i, 2) == 0) fixed.mask.row(i).setOnes();
  }
  for (const int i : held) {
    fixed.mask.row(i).setOnes();
    fixed.position.row(i) = x_release.row(i);
  }
  Points x = block.mesh.rest;
  StaticSolver solver;
  const StaticReport report = solver.solve(Vec3::Zero(), Points(), fixed, *block.model, x);
  ASSERT_TRUE(report.converged) << "relative residual " << report.relative_residual;
  Points f = Points::Zero(block.mesh.num_nodes(), 3);
  block.model->add_forces(x, Points::Zero(block.mesh.num_nodes(), 3), f);
  Vec3 static_pull = Vec3::Zero();
  for (const int i : held)
    static_pull -= row3(f, i);

  const Real stretch = x_release(held[0], 2) - block.mesh.rest(held[0], 2);
  std::printf(
      "[ %s ] release after %d steps, stretch %.3f mm: |pull| %.5f N, static %.5f N, "
      "threshold %.5f N\n",
      GetParam() == MaterialModel::mass_spring ? "mass_spring" : "corotational", step,
      1e3 * stretch, released, static_pull.norm(), settings.tear_force);
  EXPECT_LT((event->pull - static_pull).norm(), 0.05 * static_pull.norm());
  EXPECT_NEAR(released, static_pull.norm(), 0.05 * static_pull.norm());
}

INSTANTIATE_TEST_SUITE_P(Models, GraspRelease,
                         ::testing::Values(MaterialModel::mass_spring, MaterialModel::corotational),
                         [](const ::testing::TestParamInfo<MaterialModel>& info) {
                           return info.param == MaterialModel::mass_spring ? "mass_spring"
                                                                           : "corotational";
                         });

}  // namespace
}  // namespace incise::sim::tools
