#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <random>

#include "poke_fixture.h"
#include "sim/solve/active_region.h"
#include "sim/solve/symplectic_euler.h"

namespace incise::sim {
namespace {

using testing::PokeSetup;

// Thresholds for a 0.02 N poke: wake at 0.25 % of it; the bench (bench_active_region) shows the
// error in the poked region growing roughly in proportion to them.
ActiveRegionSettings poke_settings() {
  ActiveRegionSettings s;
  s.wake_force = 5e-5;
  s.sleep_force = s.wake_force / 4;
  s.sleep_speed = 1e-4;
  s.sleep_frames = 20;
  return s;
}

constexpr Real kPoke = 0.02;  // [N]
constexpr int kPulse = 20;    // steps the poke lasts

const PokeSetup& small_box() {
  static const PokeSetup setup = testing::make_poke_setup(Vec3i(10, 10, 5));  // 2500 tets
  return setup;
}

testing::LoadAt poke_load(const PokeSetup& setup) {
  return [&setup](int step, Points& f) {
    if (step < kPulse) f(setup.poked, 2) = -kPoke;
  };
}

TEST(ActiveExplicitStepper, SubModelForcesEqualTheFullModelsOnActiveAndFrontierNodes) {
  // The halo argument of active_region.h, checked at a random moving state: the mass-spring
  // damping c_ij uses both masses, so without the halo the frontier springs would differ.
  const PokeSetup& setup = small_box();
  TetMesh mesh = setup.mesh;
  std::mt19937 rng(7);
  std::uniform_real_distribution<Real> jitter(-1e-3, 1e-3);
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    for (int a = 0; a < 3; ++a) {
      mesh.x(i, a) += jitter(rng);
      mesh.v(i, a) = 10 * jitter(rng);
    }
  }
  ActiveRegionSettings s = poke_settings();
  s.wake_force = 1e9;  // no wake by force: the set is the one chosen here
  s.sleep_force = 0;
  // Sleeping nodes have no velocity (the stepper zeroes it when they fall asleep, and wakes a
  // node that starts with one): only the woken ones move.
  const std::vector<int> woken = testing::nodes_near(mesh, setup.poked, 0.025);
  Points moving = Points::Zero(mesh.num_nodes(), 3);
  for (const int node : woken)
    moving.row(node) = mesh.v.row(node);
  mesh.v = moving;
  ActiveExplicitStepper stepper(mesh, testing::mass_spring_factory(), s, setup.fixed);
  for (const int node : woken)
    EXPECT_FALSE(stepper.region().wake(node));  // woken by v
  Points x = mesh.x, v = mesh.v;
  stepper.step(setup.dt, Vec3::Zero(), Points::Zero(x.rows(), 3), x, v);

  Points full = Points::Zero(x.rows(), 3);
  testing::mass_spring_factory()(mesh)->add_forces(mesh.x, mesh.v, full);
  const std::vector<int>& complete = stepper.region().complete_nodes();
  ASSERT_GT(complete.size(), stepper.region().active_nodes().size());  // there is a frontier
  for (const int node : complete) {
    EXPECT_LT((stepper.internal_forces().row(node) - full.row(node)).norm(),
              1e-12 * full.row(node).norm() + 1e-15)
        << "node " << node;
  }
}

TEST(ActiveExplicitStepper, AllAwakeAndNeverSleepingMatchesSymplecticEulerOnTheFullModel) {
  const PokeSetup& setup = small_box();
  ActiveRegionSettings s = poke_settings();
  s.sleep_speed = 0;  // speed < 0 never holds: nothing sleeps
  ActiveExplicitStepper stepper(setup.mesh, testing::mass_spring_factory(), s, setup.fixed);
  for (int i = 0; i < setup.mesh.num_nodes(); ++i)
    stepper.region().wake(i);
  const std::vector<int> all = testing::nodes_near(setup.mesh, 0, 1.0);
  const int steps = 200;
  const testing::RunRecord full = testing::full_run(setup, steps, all, poke_load(setup));
  Points x = setup.mesh.x, v = setup.mesh.v, f(x.rows(), 3);
  for (int step = 0; step < steps; ++step) {
    f.setZero();
    poke_load(setup)(step, f);
    stepper.step(setup.dt, Vec3::Zero(), f, x, v);
    EXPECT_EQ(stepper.metrics().active_tets, setup.mesh.num_tets());
  }
  const Real scale = (full.final_x - setup.mesh.rest).cwiseAbs().maxCoeff();
  EXPECT_LT((x - full.final_x).cwiseAbs().maxCoeff(), 1e-9 * scale);
  EXPECT_EQ(stepper.rebuilds(), 1);
}

TEST(ActiveExplicitStepper, BlockAtRestStaysAsleepAndBuildsNoSubModel) {
  const PokeSetup& setup = small_box();
  ActiveExplicitStepper stepper(setup.mesh, testing::mass_spring_factory(), poke_settings(),
                                setup.fixed);
  Points x = setup.mesh.x, v = setup.mesh.v;
  const Points no_load = Points::Zero(x.rows(), 3);
  for (int step = 0; step < 2000; ++step) {
    stepper.step(setup.dt, Vec3::Zero(), no_load, x, v);
    ASSERT_EQ(stepper.metrics().active_tets, 0);
    ASSERT_EQ(stepper.metrics().evaluated_tets, 0);
  }
  EXPECT_EQ(stepper.rebuilds(), 0);  // no force was ever evaluated after construction
  EXPECT_EQ(x, setup.mesh.rest);
  EXPECT_EQ(v, setup.mesh.v);
}

TEST(ActiveExplicitStepper, PokeWakesLocallySpreadsFallsAsleepAndMatchesTheFullRun) {
  const PokeSetup& setup = small_box();
  const int steps = 1000;
  const std::vector<int> region = testing::nodes_near(setup.mesh, setup.poked, 0.02);
  const testing::RunRecord full = testing::full_run(setup, steps, region, poke_load(setup));
  const testing::RunRecord active =
      testing::active_run(setup, poke_settings(), steps, region, poke_load(setup));

  // Step 0: the poked node alone wakes (the force threshold), with its own tets only.
  EXPECT_EQ(active.metrics[0].active_nodes, 1);
  EXPECT_EQ(active.metrics[0].wakes, 1);
  EXPECT_LE(active.metrics[0].active_tets, 24);
  // The wave spreads, then everything falls asleep again.
  int peak = 0;
  long long tet_steps = 0;
  for (const ActiveRegionMetrics& m : active.metrics) {
    peak = std::max(peak, m.active_tets);
    tet_steps += m.active_tets;
  }
  EXPECT_GT(peak, 10 * active.metrics[0].active_tets);
  EXPECT_EQ(active.metrics.back().active_nodes, 0);
  EXPECT_EQ(active.metrics.back().active_tets, 0);
  // Far fewer tets integrated than the full run's steps x #tets.
  EXPECT_LT(tet_steps, steps * static_cast<long long>(setup.mesh.num_tets()) / 5);
  // The poked region follows the full simulation within 2 % of its peak displacement.
  const testing::RegionError e = testing::region_error(active, full, setup.mesh.rest, region);
  EXPECT_GT(e.peak_displacement, 1e-4);
  EXPECT_LT(e.max_error, 0.02 * e.peak_displacement);
}

TEST(ActiveExplicitStepper, MetricsCountTheSetsActuallyIntegrated) {
  const PokeSetup& setup = small_box();
  ActiveExplicitStepper stepper(setup.mesh, testing::mass_spring_factory(), poke_settings(),
                                setup.fixed);
  Points x = setup.mesh.x, v = setup.mesh.v, f(x.rows(), 3);
  int max_active = 0;
  for (int step = 0; step < 300; ++step) {
    f.setZero();
    poke_load(setup)(step, f);
    const Points x_before = x;
    stepper.step(setup.dt, Vec3::Zero(), f, x, v);
    const ActiveRegionMetrics& m = stepper.metrics();
    const ActiveRegion& region = stepper.region();
    // The integrated nodes: those active now and those that fell asleep at the end of the step.
    int active_now = 0;
    for (int i = 0; i < setup.mesh.num_nodes(); ++i)
      active_now += region.node_active(i) ? 1 : 0;
    ASSERT_EQ(m.active_nodes, active_now + m.sleeps);
    ASSERT_EQ(m.active_nodes, static_cast<int>(region.active_nodes().size()));
    // Only integrated nodes moved.
    std::vector<std::uint8_t> integrated(setup.mesh.num_nodes(), 0);
    for (const int i : region.active_nodes())
      integrated[i] = 1;
    for (int i = 0; i < setup.mesh.num_nodes(); ++i) {
      if (integrated[i] == 0) {
        ASSERT_EQ(x.row(i), x_before.row(i)) << "step " << step;
      }
    }
    int tets = 0;
    for (int t = 0; t < setup.mesh.num_tets(); ++t) {
      bool any = false;
      for (int k = 0; k < 4; ++k)
        any = any || integrated[setup.mesh.tets(t, k)] != 0;
      tets += any ? 1 : 0;
    }
    ASSERT_EQ(m.active_tets, tets);
    ASSERT_GE(m.evaluated_tets, static_cast<int>(region.evaluated_tets().size()));
    max_active = std::max(max_active, m.active_tets);
  }
  EXPECT_GT(max_active, 0);
}

TEST(ActiveExplicitStepper, SleepingBodyWakesUnderAConstantLoadAboveTheThresholdOnly) {
  const PokeSetup& setup = small_box();
  std::vector<int> top;
  const Real height = setup.mesh.rest.col(2).maxCoeff();
  for (int i = 0; i < setup.mesh.num_nodes(); ++i) {
    if (setup.mesh.rest(i, 2) == height) top.push_back(i);
  }
  const ActiveRegionSettings s = poke_settings();
  for (const Real per_node : {0.5 * s.wake_force, 20 * s.wake_force}) {
    const testing::LoadAt load = [&](int, Points& f) {
      for (const int i : top)
        f(i, 0) = per_node;  // a shear load: unbalanced at rest
    };
    const int steps = 1500;
    const testing::RunRecord full = testing::full_run(setup, steps, top, load);
    const testing::RunRecord active = testing::active_run(setup, s, steps, top, load);
    if (per_node < s.wake_force) {
      for (const ActiveRegionMetrics& m : active.metrics)
        ASSERT_EQ(m.active_nodes, 0);
      EXPECT_EQ(active.final_x, setup.mesh.rest);
      continue;
    }
    EXPECT_EQ(active.metrics[0].wakes, static_cast<int>(top.size()));
    // It settles under the load and falls asleep at (near) the full run's equilibrium.
    EXPECT_EQ(active.metrics.back().active_nodes, 0);
    const testing::RegionError e = testing::region_error(active, full, setup.mesh.rest, top);
    const Real final_shift = (full.final_x - setup.mesh.rest).rowwise().norm().maxCoeff();
    EXPECT_GT(final_shift, 1e-4);
    EXPECT_LT((active.final_x - full.final_x).rowwise().norm().maxCoeff(), 0.02 * final_shift);
    EXPECT_LT(e.max_error, 0.02 * e.peak_displacement);
  }
}

TEST(ActiveExplicitStepper, ContactWakeOfANodeAtRestFallsAsleepUnmoved) {
  const PokeSetup& setup = small_box();
  const ActiveRegionSettings s = poke_settings();
  ActiveExplicitStepper stepper(setup.mesh, testing::mass_spring_factory(), s, setup.fixed);
  Points x = setup.mesh.x, v = setup.mesh.v;
  const Points no_load = Points::Zero(x.rows(), 3);
  EXPECT_TRUE(stepper.region().wake(setup.poked));
  for (int step = 0; step < s.sleep_frames; ++step) {
    stepper.step(setup.dt, Vec3::Zero(), no_load, x, v);
    EXPECT_EQ(stepper.metrics().active_nodes, 1);
  }
  EXPECT_EQ(stepper.metrics().sleeps, 1);
  stepper.step(setup.dt, Vec3::Zero(), no_load, x, v);
  EXPECT_EQ(stepper.metrics().active_tets, 0);
  EXPECT_EQ(x, setup.mesh.rest);
}

}  // namespace
}  // namespace incise::sim
