// The forward model of calibration (sim/calibrate/linear_response.h): linearised backward Euler
// on a one-node oscillator against its closed forms, and on seed 004's cube against the product's
// own mass-spring model stepped by ImplicitEuler (sim/solve/implicit_euler.h).
#include <gtest/gtest.h>

#include <cmath>

#include "sim/calibrate/calibration.h"
#include "sim/calibrate/cube_experiment.h"
#include "sim/scene/scene_run.h"
#include "sim/solve/implicit_euler.h"

namespace incise::sim::calibrate {
namespace {

// Node 0 fixed, node 1 of mass m on a spring k (and dashpot c) along z; a force F along z from
// the first step.
struct Oscillator {
  Real m = 0.01, k = 40, c = 0, force = 0.002, h = 0.002;
  int steps = 400;

  Points simulate() const {
    VecX masses(2);
    masses << 1, m;
    ProbeExperiment e;
    e.node = 1;
    e.force = Points::Zero(steps, 3);
    e.force.col(2).setConstant(force);
    e.measured = Points::Zero(steps, 3);
    LinearResponse response(masses, {1, 0}, h, {e});
    Triplets stiffness, damping;
    for (const auto& [i, j, sign] : {std::tuple{0, 0, 1}, {1, 1, 1}, {0, 1, -1}, {1, 0, -1}}) {
      stiffness.emplace_back(3 * i + 2, 3 * j + 2, sign * k);
      damping.emplace_back(3 * i + 2, 3 * j + 2, sign * c);
    }
    std::vector<Points> u;
    EXPECT_TRUE(response.simulate(stiffness, damping, u));
    return u.at(0);
  }
};

TEST(LinearResponse, ADampedOscillatorSettlesAtForceOverStiffness) {
  Oscillator o;
  o.c = 2 * std::sqrt(o.k * o.m) * 0.3;
  o.steps = 3000;
  const Points u = o.simulate();
  EXPECT_NEAR(u(o.steps - 1, 2), o.force / o.k, 1e-12);
  EXPECT_EQ(u(o.steps - 1, 0), 0.0);  // nothing pushes across
  EXPECT_EQ(u(o.steps - 1, 1), 0.0);
}

// Backward Euler multiplies an undamped oscillator's energy k e^2 + m v^2 (e the distance from
// the equilibrium F / k) by exactly 1 / (1 + (omega h)^2) each step.
TEST(LinearResponse, AnUndampedOscillatorLosesBackwardEulersEnergyFactorEachStep) {
  Oscillator o;
  const Points u = o.simulate();
  const Real omega = std::sqrt(o.k / o.m);
  const Real factor = 1 / (1 + omega * omega * o.h * o.h);
  const auto energy = [&](int step) {
    const Real previous = step == 0 ? 0 : u(step - 1, 2);
    const Real v = (u(step, 2) - previous) / o.h;  // x1 = x0 + h v1: exact for the scheme
    const Real e = u(step, 2) - o.force / o.k;
    return o.k * e * e + o.m * v * v;
  };
  for (int step = 1; step < 50; ++step) {
    EXPECT_NEAR(energy(step) / energy(step - 1), factor, 1e-9) << "step " << step;
  }
}

// The cube's pushes move a node by about 1 % of the edge: the product's nonlinear mass-spring
// model, stepped by ImplicitEuler at the same step, follows the linearisation to well under the
// noise of any measurement.
TEST(LinearResponse, FollowsTheProductsMassSpringModelOnSeed004sCube) {
  const CubeExperiment cube = seed004_cube(kCubeModulus);
  const MaterialParameters parameters = MaterialParameters::node_moduli(cube.scene, cube.mesh, 0);
  const ProbeData linear =
      simulate_probe_data(cube.scene, cube.mesh, parameters, parameters.start(), cube.pushes);

  const std::vector<char> fixed = fixed_nodes(cube.scene, cube.mesh);
  const std::vector<ProbeExperiment> experiments =
      attach_probe_data(cube.pushes, cube.mesh.rest, fixed, 1e-9);
  for (std::size_t e = 0; e < experiments.size(); ++e) {
    const std::unique_ptr<Model> model = make_model(cube.scene, cube.mesh);
    ImplicitEulerSettings settings;
    settings.linear.cg.tolerance = 1e-12;
    settings.linear.cg.max_iterations = 2000;
    ImplicitEuler integrator(settings);
    Prescribed prescribed;
    prescribed.mask = AxisMask::Zero(cube.mesh.num_nodes(), 3);
    prescribed.position = cube.mesh.rest;
    for (int i = 0; i < cube.mesh.num_nodes(); ++i) {
      if (fixed[static_cast<std::size_t>(i)]) prescribed.mask.row(i).setOnes();
    }
    Points x = cube.mesh.rest;
    Points v = Points::Zero(x.rows(), 3);
    Points force = Points::Zero(x.rows(), 3);
    const int node = experiments[e].node;
    Real largest = 0, difference = 0;
    for (int k = 0; k < kCubeSamples; ++k) {
      force.row(node) = experiments[e].force.row(k);
      ASSERT_TRUE(
          integrator.step(cube.pushes.step, Vec3::Zero(), force, prescribed, *model, x, v).finite);
      const Vec3 nonlinear = row3(x, node) - row3(cube.mesh.rest, node);
      const Vec3 linearised = linear.contacts[e].samples[static_cast<std::size_t>(k + 1)].position -
                              linear.contacts[e].samples[0].position;
      largest = std::max(largest, linearised.norm());
      difference = std::max(difference, (nonlinear - linearised).norm());
    }
    EXPECT_GT(largest, 0.005 * kCubeEdge) << "push " << e;  // a real push, not a rounding error
    EXPECT_LT(difference, 0.02 * largest) << "push " << e;
  }
}

TEST(LinearResponse, AProbeAwayFromTheTissueIsNoContact) {
  const CubeExperiment cube = seed004_cube(kCubeModulus);
  ProbeData far = cube.pushes;
  for (auto& s : far.contacts[2].samples)
    s.position.x() += 0.02;  // 2 cm beside the cube
  const std::vector<char> fixed = fixed_nodes(cube.scene, cube.mesh);
  try {
    attach_probe_data(far, cube.mesh.rest, fixed, 0.003);
    FAIL() << "a probe 2 cm away attached";
  } catch (const CalibrationError& e) {
    EXPECT_NE(std::string(e.what()).find("contact 2: the probe starts at"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("no contact"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace incise::sim::calibrate
