#include "sim/solve/adaptive_explicit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "test_models.h"

namespace incise::sim {
namespace {

const Vec3 kNoGravity = Vec3::Zero();
const Points kNoForces;
const Prescribed kNothingPrescribed{};

// Oscillator with period 1 s started at x = A, v = 0: x(t) = A cos(2 pi t).
struct Oscillator {
  static constexpr Real kAmplitude = 0.01;
  const Real omega = 2 * std::numbers::pi;
  testing::LinearModel model = testing::make_oscillator(1, omega* omega);
  Points x = Points::Zero(1, 3), v = Points::Zero(1, 3);
  Oscillator() { x(0, 0) = kAmplitude; }
};

TEST(AdaptiveExplicit, GlobalErrorFollowsTheTolerance) {
  Real previous_error = 0;
  for (const Real tolerance : {1e-6, 1e-8, 1e-10}) {
    Oscillator o;
    AdaptiveExplicitSettings settings;
    settings.position_tolerance = tolerance;
    settings.velocity_tolerance = tolerance * o.omega;
    settings.dt_initial = 1e-3;
    settings.dt_min = 1e-9;
    settings.dt_max = 0.1;
    AdaptiveExplicit integrator(settings);
    const ExplicitReport report =
        integrator.advance(2.0, kNoGravity, kNoForces, kNothingPrescribed, o.model, o.x, o.v);
    ASSERT_TRUE(report.completed && report.finite);
    EXPECT_EQ(report.clamped_steps, 0);
    EXPECT_LE(report.error_estimate, 1);
    const Real error = std::abs(o.x(0, 0) - Oscillator::kAmplitude);  // two full periods
    std::printf("tolerance %.0e: %d steps (%d rejected), error %.3e m\n", tolerance, report.steps,
                report.rejected_steps, error);
    // Local errors below tolerance add up to at most steps x tolerance.
    EXPECT_LT(error, report.steps * tolerance);
    if (previous_error > 0) {
      EXPECT_LT(error, previous_error / 10);
    }
    previous_error = error;
  }
}

TEST(AdaptiveExplicit, FloorsAtDtMinAndSaysSo) {
  Oscillator o;
  AdaptiveExplicitSettings settings;
  settings.position_tolerance = 1e-15;  // unreachable at dt_min
  settings.velocity_tolerance = 1e-15;
  settings.dt_min = 1e-2;
  settings.dt_initial = 1e-2;
  settings.dt_max = 1e-2;
  AdaptiveExplicit integrator(settings);
  const ExplicitReport report =
      integrator.advance(0.5, kNoGravity, kNoForces, kNothingPrescribed, o.model, o.x, o.v);
  EXPECT_TRUE(report.completed);
  EXPECT_NEAR(report.steps, 50, 1);
  EXPECT_EQ(report.clamped_steps, report.steps);
  EXPECT_EQ(report.rejected_steps, 0);
  EXPECT_GT(report.error_estimate, 1);
  EXPECT_NEAR(report.min_dt_used, 1e-2, 1e-12);
  EXPECT_DOUBLE_EQ(integrator.next_dt(), 1e-2);
  // Still accurate to the method's order at this step: half a period later x = -A.
  EXPECT_NEAR(o.x(0, 0), -Oscillator::kAmplitude, 1e-3 * Oscillator::kAmplitude);
}

TEST(AdaptiveExplicit, ReportsABlowUpAtTheFloorInsteadOfNaN) {
  // omega = 1e4 1/s with a floor of 1 ms: omega dt_min = 10, far outside the method's stability.
  testing::LinearModel model = testing::make_oscillator(1, 1e8);
  Points x = Points::Zero(1, 3), v = Points::Zero(1, 3);
  x(0, 0) = 1;
  AdaptiveExplicitSettings settings;
  settings.dt_min = settings.dt_initial = 1e-3;
  settings.dt_max = 1e-3;
  AdaptiveExplicit integrator(settings);
  const ExplicitReport report =
      integrator.advance(10.0, kNoGravity, kNoForces, kNothingPrescribed, model, x, v);
  EXPECT_FALSE(report.finite);
  EXPECT_FALSE(report.completed);
  EXPECT_TRUE(x.allFinite() && v.allFinite());
}

TEST(AdaptiveExplicit, StepCapStopsTheCall) {
  Oscillator o;
  AdaptiveExplicitSettings settings;
  settings.dt_min = settings.dt_initial = settings.dt_max = 1e-3;
  settings.max_steps = 5;
  AdaptiveExplicit integrator(settings);
  const ExplicitReport report =
      integrator.advance(1.0, kNoGravity, kNoForces, kNothingPrescribed, o.model, o.x, o.v);
  EXPECT_FALSE(report.completed);
  EXPECT_TRUE(report.finite);
  EXPECT_EQ(report.steps + report.rejected_steps, 5);
}

TEST(AdaptiveExplicit, PrescribedCoordinatesEndOnTheirValuesAndPullTheRest) {
  testing::LinearModel model = testing::make_spring_pair(10);
  const Points rest = model.rest();
  Prescribed driven{AxisMask::Zero(2, 3), rest};
  driven.mask.row(0).setOnes();
  driven.position(0, 0) = 0.123456789;
  Points x = rest, v = Points::Zero(2, 3);
  AdaptiveExplicit integrator(AdaptiveExplicitSettings{});
  const ExplicitReport report =
      integrator.advance(0.05, Vec3(0, 0, -9.81), kNoForces, driven, model, x, v);
  ASSERT_TRUE(report.completed);
  EXPECT_EQ(row3(x, 0), row3(driven.position, 0));
  EXPECT_DOUBLE_EQ(v(0, 0), 0.123456789 / 0.05);
  EXPECT_GT(x(1, 0), 1);  // pulled along
  EXPECT_NEAR(x(1, 2), -0.5 * 9.81 * 0.05 * 0.05,
              5e-3 * 9.81 * 0.05 * 0.05);  // falls (the spring holds back 0.2%)
}

TEST(AdaptiveExplicit, RejectsBadSettings) {
  AdaptiveExplicitSettings settings;
  settings.dt_min = 1;  // above dt_initial
  EXPECT_THROW(AdaptiveExplicit{settings}, std::invalid_argument);
  settings = {};
  settings.position_tolerance = 0;
  EXPECT_THROW(AdaptiveExplicit{settings}, std::invalid_argument);
}

}  // namespace
}  // namespace incise::sim
