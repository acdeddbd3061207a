#include "sim/solve/central_difference.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sim/mesh/box_mesher.h"
#include "sim/solve/stable_time_step.h"
#include "test_models.h"

namespace incise::sim {
namespace {

const Vec3 kNoGravity = Vec3::Zero();
const Points kNoForces;
const Prescribed kNothingPrescribed{};

// The bottom face (z = 0) of a mesh held at rest.
Prescribed hold_bottom(const TetMesh& mesh) {
  Prescribed held{AxisMask::Zero(mesh.num_nodes(), 3), mesh.rest};
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (mesh.rest(i, 2) == 0) held.mask.row(i).setOnes();
  }
  return held;
}

TEST(CentralDifference, OscillatorFollowsTheDiscreteClosedFormFor10000Steps) {
  // x_n = A cos(n theta), cos theta = 1 - (omega h)^2 / 2: amplitude kept exactly, period
  // 2 pi h / theta, slightly longer than 2 pi / omega.
  const Real m = 2, k = 50, amplitude = 0.01;
  const Real omega = std::sqrt(k / m);
  const Real h = 0.1 / omega;
  testing::LinearModel model = testing::make_oscillator(m, k);
  Points x = Points::Zero(1, 3), v = Points::Zero(1, 3);
  x(0, 0) = amplitude;
  const Real theta = std::acos(1 - (omega * h) * (omega * h) / 2);
  const Real energy0 = testing::total_energy(model, x, v);
  CentralDifference integrator;
  Real max_error = 0, max_energy_deviation = 0, last_upward_crossing = -1;
  int crossings = 0;
  Real first_upward_crossing = -1;
  for (int n = 1; n <= 10000; ++n) {
    const Real before = x(0, 0);
    const ExplicitReport report =
        integrator.step(h, kNoGravity, kNoForces, kNothingPrescribed, model, x, v);
    ASSERT_TRUE(report.finite);
    max_error = std::max(max_error, std::abs(x(0, 0) - amplitude * std::cos(n * theta)));
    max_energy_deviation = std::max(
        max_energy_deviation, std::abs(testing::total_energy(model, x, v) - energy0) / energy0);
    if (before < 0 && x(0, 0) >= 0) {  // upward zero crossing, linearly interpolated
      const Real t = (n - 1 + before / (before - x(0, 0))) * h;
      if (first_upward_crossing < 0) first_upward_crossing = t;
      last_upward_crossing = t;
      ++crossings;
    }
  }
  EXPECT_LT(max_error, 1e-9 * amplitude);
  const Real period = (last_upward_crossing - first_upward_crossing) / (crossings - 1);
  EXPECT_NEAR(period, 2 * std::numbers::pi * h / theta, 1e-6 * period);
  // The discrete energy oscillates by O((omega h)^2) and does not drift.
  EXPECT_LT(max_energy_deviation, (omega * h) * (omega * h) / 2);
  EXPECT_TRUE(row3(x, 0).allFinite());
}

TEST(CentralDifference, StableAtTheEstimatedStepOnATetMesh) {
  const TetMesh mesh = make_box_mesh(Vec3(0.03, 0.02, 0.02), Vec3i(3, 2, 2));
  const Real E = 5e3, nu = 0.3, rho = 1000;
  testing::LinearModel model = testing::make_linear_tet_model(mesh, E, nu, rho);
  const Prescribed held = hold_bottom(mesh);
  Points x = mesh.rest, v = Points::Zero(mesh.num_nodes(), 3);
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (held.mask(i, 0) == 0)
      x.row(i) += 1e-3 * Vec3(std::sin(i), std::cos(3 * i), 0.5).transpose();
  }
  const Real energy0 = testing::total_energy(model, x, v);
  const Real h = stable_time_step(mesh, E, nu, rho);
  CentralDifference integrator;
  Real max_energy = 0;
  for (int n = 0; n < 5000; ++n) {
    ASSERT_TRUE(integrator.step(h, kNoGravity, kNoForces, held, model, x, v).finite);
    max_energy = std::max(max_energy, testing::total_energy(model, x, v));
  }
  EXPECT_LT(max_energy, 1.05 * energy0);
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (held.mask(i, 0) != 0) {
      EXPECT_EQ(row3(x, i), row3(mesh.rest, i));
    }
  }
}

TEST(CentralDifference, ReportsABlowUpInsteadOfNaNFarAboveTheLimit) {
  const TetMesh mesh = make_box_mesh(Vec3(0.03, 0.02, 0.02), Vec3i(3, 2, 2));
  testing::LinearModel model = testing::make_linear_tet_model(mesh, 5e3, 0.3, 1000);
  const Prescribed held = hold_bottom(mesh);
  Points x = mesh.rest, v = Points::Zero(mesh.num_nodes(), 3);
  x(mesh.num_nodes() - 1, 2) += 1e-3;
  const Real h = 10 * stable_time_step(mesh, 5e3, 0.3, 1000);
  CentralDifference integrator;
  int steps = 0;
  bool blown_up = false;
  while (steps < 10000 && !blown_up) {
    const Points x_before = x, v_before = v;
    const ExplicitReport report = integrator.step(h, kNoGravity, kNoForces, held, model, x, v);
    blown_up = !report.finite;
    if (blown_up) {
      EXPECT_FALSE(report.completed);
      EXPECT_EQ(report.steps, 0);
      EXPECT_EQ(x, x_before);  // the last finite state is kept
      EXPECT_EQ(v, v_before);
    }
    ++steps;
  }
  EXPECT_TRUE(blown_up) << "10 x the stable step must diverge";
  EXPECT_TRUE(x.allFinite() && v.allFinite());
}

TEST(CentralDifference, PrescribedCoordinatesEndOnTheirValues) {
  // Two nodes on a spring (x axis); node 0 is driven, node 1 free.
  testing::LinearModel model = testing::make_spring_pair(10);
  const Points rest = model.rest();
  Prescribed driven{AxisMask::Zero(2, 3), rest};
  driven.mask.row(0).setOnes();
  Points x = rest, v = Points::Zero(2, 3);
  CentralDifference integrator;
  const Real h = 0.01;
  for (int n = 1; n <= 100; ++n) {
    const Points x_old = x;
    driven.position(0, 0) = 0.3 * std::sin(0.05 * n) + 1e-17 * n;
    ASSERT_TRUE(integrator.step(h, Vec3(0, 0, -9.81), kNoForces, driven, model, x, v).finite);
    EXPECT_EQ(x(0, 0), driven.position(0, 0));
    EXPECT_EQ(x(0, 2), 0);  // gravity does not move a held coordinate
    EXPECT_DOUBLE_EQ(v(0, 0), (driven.position(0, 0) - x_old(0, 0)) / h);
  }
  EXPECT_GT(std::abs(x(1, 0) - 1), 1e-3);  // the free node followed
  EXPECT_LT(x(1, 2), -1e-3);               // and fell
}

TEST(CentralDifference, DampedBodySettlesToRest) {
  const TetMesh mesh = make_box_mesh(Vec3(0.03, 0.02, 0.02), Vec3i(3, 2, 2));
  testing::LinearModel model = testing::make_linear_tet_model(mesh, 5e3, 0.3, 1000, 20.0);
  const Prescribed held = hold_bottom(mesh);
  Points x = mesh.rest, v = Points::Zero(mesh.num_nodes(), 3);
  x(mesh.num_nodes() - 1, 2) += 2e-3;
  const Real energy0 = testing::total_energy(model, x, v);
  const Real h = stable_time_step(mesh, 5e3, 0.3, 1000);
  CentralDifference integrator;
  const int steps = static_cast<int>(1.0 / h);  // 1 s, 20 e-folds of alpha = 20 1/s
  for (int n = 0; n < steps; ++n)
    integrator.step(h, kNoGravity, kNoForces, held, model, x, v);
  EXPECT_LT(testing::total_energy(model, x, v), 1e-6 * energy0);
  EXPECT_LT((x - mesh.rest).cwiseAbs().maxCoeff(), 1e-5);
}

TEST(CentralDifference, RejectsBadInput) {
  testing::LinearModel model = testing::make_oscillator(1, 1);
  Points x = Points::Zero(1, 3), v = Points::Zero(1, 3);
  CentralDifference integrator;
  EXPECT_THROW(integrator.step(0, kNoGravity, kNoForces, kNothingPrescribed, model, x, v),
               std::invalid_argument);
  Points wrong = Points::Zero(2, 3);
  EXPECT_THROW(integrator.step(0.1, kNoGravity, kNoForces, kNothingPrescribed, model, wrong, v),
               std::invalid_argument);
  Prescribed bad{AxisMask::Ones(1, 3), Points::Constant(1, 3, std::nan(""))};
  EXPECT_THROW(integrator.step(0.1, kNoGravity, kNoForces, bad, model, x, v),
               std::invalid_argument);
}

}  // namespace
}  // namespace incise::sim
