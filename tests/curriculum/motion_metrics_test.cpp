// Tests for curriculum/motion_metrics.h: each metric against a closed form derived here (circle,
// straight line, fixed-axis rotation, pause, minimum-jerk reach), invariances of the jerk measure
// (sampling rate, amplitude), two-hand overlap, and the exact errors for bad input.
#include "curriculum/motion_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "curriculum/metric_catalogue.h"
#include "metric_test_helpers.h"

namespace incise::curriculum {
namespace {

using Vec = std::array<double, 3>;

const double pi = std::numbers::pi;

using testing::error_of;
using testing::metric;

// #steps + 1 samples at t = T i / steps of a tip moving along #tip(t); orientation identity, jaw
// closed, no force.
std::vector<HandSample> sampled(double duration, int steps, const std::function<Vec(double)>& tip) {
  std::vector<HandSample> samples(steps + 1);
  for (int i = 0; i <= steps; ++i) {
    samples[i].t_s = duration * i / steps;
    samples[i].tip_m = tip(samples[i].t_s);
  }
  return samples;
}

// Along x at #speed, except for a still pause over [pause_from, pause_from + pause).
Vec move_pause_move(double t, double speed, double pause_from, double pause) {
  const double moving_time = t < pause_from ? t : std::max(pause_from, t - pause);
  return {speed * moving_time, 0, 0};
}

TEST(HandMetrics, ReportsTheElevenMetricsInOrderWithUnitsAndOneLineDefinitions) {
  const auto values = hand_metrics({});
  const std::vector<std::pair<std::string, std::string>> expected = {
      {"path_length_m", "m"},         {"angular_path_rad", "rad"}, {"economy_of_motion", ""},
      {"movements", "count"},         {"idle_time_s", "s"},        {"mean_speed_m_s", "m/s"},
      {"log_dimensionless_jerk", ""}, {"peak_force_n", "N"},       {"rms_force_n", "N"},
      {"integrated_force_ns", "N s"}, {"jaw_closures", "count"}};
  ASSERT_EQ(values.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(values[i].key, expected[i].first);
    EXPECT_EQ(values[i].unit, expected[i].second);
    // Named and defined in the catalogue, in the unit it is computed in.
    const auto info = find_metric(values[i].key);
    ASSERT_TRUE(info) << values[i].key;
    EXPECT_EQ(info->unit, values[i].unit) << values[i].key;
    if (values[i].key == "log_dimensionless_jerk")
      EXPECT_TRUE(std::isnan(values[i].value)) << "undefined without motion";
    else
      EXPECT_EQ(values[i].value, 0.0) << "an empty run measures nothing: " << values[i].key;
  }
}

TEST(HandMetrics, CircleAtConstantSpeedMatchesTheClosedForms) {
  // One lap of radius r in T = 2 s at 500 Hz: N = 1000 steps, angle step dphi = 2 pi / N.
  const double r = 0.05;
  const double duration = 2.0;
  const int steps = 1000;
  const double v = 2 * pi * r / duration;  // 0.157 m/s, well above the moving threshold
  const double omega = v / r;
  const auto hand = sampled(duration, steps, [&](double t) {
    return Vec{r * std::cos(omega * t), r * std::sin(omega * t), 0.02};
  });
  const auto values = hand_metrics(hand);

  // Each step is a chord 2 r sin(dphi / 2); with x - x^3/6 <= sin x <= x the inscribed polygon is
  // at most 2 pi r (pi / N)^2 / 6 shorter than the circle.
  const double circumference = 2 * pi * r;
  const double chord_deficit = circumference * (pi / steps) * (pi / steps) / 6;
  const double path = metric(values, "path_length_m");
  EXPECT_LE(path, circumference);
  EXPECT_GE(path, circumference - chord_deficit);
  EXPECT_NEAR(metric(values, "mean_speed_m_s"), v, v * (pi / steps) * (pi / steps) / 6);
  // Start and end coincide up to the rounding of cos(2 pi), sin(2 pi).
  EXPECT_NEAR(metric(values, "economy_of_motion"), 0.0, 1e-12);
  EXPECT_EQ(metric(values, "idle_time_s"), 0.0);
  EXPECT_EQ(metric(values, "movements"), 1.0) << "moving from the first sample to the last";
  EXPECT_EQ(metric(values, "angular_path_rad"), 0.0) << "the tool's orientation is fixed";

  // Uniform circular motion: |d^2v/dt^2| = r omega^3 = v^3 / r^2 at all times, so
  // LDLJ = -ln(T^3 / v^2 * (v^3 / r^2)^2 * T) = -ln((v T / r)^4) = -4 ln(2 pi) for one lap.
  // Discretely, the third difference of the circle has magnitude r (2 sin(omega dt / 2) / dt)^3,
  // relatively (omega dt)^2 / 8 below r omega^3, and the peak (one-sided, end) speed is the chord
  // speed v sin(omega dt / 2) / (omega dt / 2), relatively (omega dt)^2 / 24 low. Together the
  // logarithm's argument is off by at most (omega dt)^2 (2 / 8 + 2 / 24) = 5.3e-6 relatively.
  const double omega_dt = omega * duration / steps;
  EXPECT_NEAR(metric(values, "log_dimensionless_jerk"), -4 * std::log(2 * pi),
              2 * omega_dt * omega_dt * (2.0 / 8 + 2.0 / 24));
}

TEST(HandMetrics, StraightLineAtConstantSpeedIsFullyEconomicalWithoutRotation) {
  const Vec from = {0.01, -0.02, 0.03};
  const Vec to = {0.07, 0.05, -0.01};
  const double length = std::hypot(to[0] - from[0], to[1] - from[1], to[2] - from[2]);
  const double duration = 1.5;
  const auto hand = sampled(duration, 750, [&](double t) {
    const double s = t / duration;
    return Vec{from[0] + s * (to[0] - from[0]), from[1] + s * (to[1] - from[1]),
               from[2] + s * (to[2] - from[2])};
  });
  const auto values = hand_metrics(hand);
  EXPECT_NEAR(metric(values, "path_length_m"), length, 1e-12);
  EXPECT_NEAR(metric(values, "economy_of_motion"), 1.0, 1e-12);
  EXPECT_LE(metric(values, "economy_of_motion"), 1.0);
  EXPECT_EQ(metric(values, "angular_path_rad"), 0.0);
  EXPECT_NEAR(metric(values, "mean_speed_m_s"), length / duration, 1e-12);
  EXPECT_EQ(metric(values, "movements"), 1.0);
  EXPECT_EQ(metric(values, "idle_time_s"), 0.0);
}

TEST(HandMetrics, RotationAboutAFixedAxisTurnsThroughRateTimesDuration) {
  // q(t) = (cos(w t / 2), sin(w t / 2) n): consecutive orientations differ by w dt about n, so the
  // angular path is w T, also beyond pi (here 4.5 rad) since it sums the steps.
  const double w = 1.5;
  const double duration = 3.0;
  const Vec axis = {1.0 / 3, 2.0 / 3, 2.0 / 3};
  auto hand = sampled(duration, 1500, [](double) { return Vec{0.1, 0.2, 0.3}; });
  for (auto& s : hand) {
    const double half = 0.5 * w * s.t_s;
    s.orientation = {std::cos(half), std::sin(half) * axis[0], std::sin(half) * axis[1],
                     std::sin(half) * axis[2]};
  }
  const auto values = hand_metrics(hand);
  EXPECT_NEAR(metric(values, "angular_path_rad"), w * duration, 1e-9);
  // The tip itself never moves: no path, no movement, idle throughout, smoothness undefined.
  EXPECT_EQ(metric(values, "path_length_m"), 0.0);
  EXPECT_EQ(metric(values, "economy_of_motion"), 0.0);
  EXPECT_EQ(metric(values, "movements"), 0.0);
  EXPECT_NEAR(metric(values, "idle_time_s"), duration, 1e-12);
  EXPECT_TRUE(std::isnan(metric(values, "log_dimensionless_jerk")));
}

TEST(HandMetrics, RotationAngleIgnoresTheQuaternionSign) {
  // q and -q are the same orientation: flipping the sign every sample adds no angle.
  auto hand = sampled(1.0, 10, [](double) { return Vec{}; });
  for (std::size_t i = 0; i < hand.size(); ++i)
    hand[i].orientation =
        i % 2 ? std::array<double, 4>{-0.6, 0, -0.8, 0} : std::array<double, 4>{0.6, 0, 0.8, 0};
  EXPECT_NEAR(metric(hand_metrics(hand), "angular_path_rad"), 0.0, 1e-12);
}

TEST(HandMetrics, MovePauseMoveCountsTwoMovementsAndThePauseAsIdle) {
  // 1 s at v, 0.5 s still, 1 s at v; 500 Hz (dt = 2 ms).
  const double v = 0.1;
  const double pause = 0.5;
  const double dt = 0.002;
  const auto hand = sampled(2.5, 1250, [&](double t) { return move_pause_move(t, v, 1.0, pause); });

  // Without smoothing: the samples at the pause's two ends have the central-difference speed v/2
  // (one step moved out of two), the samples strictly inside have 0. Those stand for the time from
  // halfway after the first end to halfway before the last: pause - dt.
  MotionThresholds raw;
  raw.smoothing_s = 0;
  const auto unsmoothed = hand_metrics(hand, raw);
  EXPECT_NEAR(metric(unsmoothed, "idle_time_s"), pause, dt) << "within one sample";
  EXPECT_NEAR(metric(unsmoothed, "idle_time_s"), pause - dt, 1e-9);
  EXPECT_EQ(metric(unsmoothed, "movements"), 2.0);

  // With the default moving average of width w = 2 h: the speed ramp v, v/2, 0 over the samples
  // around the pause's start integrates like a step at the start t_a, so a window containing it
  // averages v (t_a - (t - h)) / (2 h). That is below the still speed once
  // t > t_a + h - 2 h still / v, and symmetrically at the end, so the idle time is
  // pause - w (1 - 2 still / v), to within the sample granularity (dt at each end).
  const MotionThresholds th;
  const auto smoothed = hand_metrics(hand, th);
  EXPECT_NEAR(metric(smoothed, "idle_time_s"),
              pause - th.smoothing_s * (1 - 2 * th.still_speed_m_s / v), 2 * dt);
  EXPECT_EQ(metric(smoothed, "movements"), 2.0);
}

TEST(HandMetrics, PauseShorterThanMinIdleIsNotIdleButStillSplitsMovements) {
  // A 0.1 s pause (< min_idle_s = 0.2 s): the tip is still long enough to re-arm the movement
  // detection (the smoothed speed is 0 over about 0.1 - 0.02 s) but not long enough to be idle.
  const auto hand = sampled(2.1, 1050, [&](double t) { return move_pause_move(t, 0.1, 1.0, 0.1); });
  const auto values = hand_metrics(hand);
  EXPECT_EQ(metric(values, "idle_time_s"), 0.0);
  EXPECT_EQ(metric(values, "movements"), 2.0);
}

// A minimum-jerk reach of #distance along a fixed direction in T = 1 s, plus an optional
// oscillation of #amplitude at #frequency along a perpendicular direction.
std::vector<HandSample> minimum_jerk_reach(int steps, double distance, double amplitude = 0,
                                           double frequency = 0) {
  return sampled(1.0, steps, [&](double t) {
    const double s = t;  // T = 1
    const double x = distance * (10 * s * s * s - 15 * s * s * s * s + 6 * s * s * s * s * s);
    const double y = amplitude * std::sin(2 * pi * frequency * t);
    return Vec{0.6 * x, 0.8 * x, y};
  });
}

// Minimum-jerk reach x = D (10 s^3 - 15 s^4 + 6 s^5), s = t / T:
//   v = 30 D / T s^2 (1 - s)^2, peak 15 D / (8 T) at s = 1/2;
//   jerk = 60 D / T^3 (1 - 6 s + 6 s^2), and the integral over s of (1 - 6 s + 6 s^2)^2 is
//   1 - 6 + 16 - 18 + 36/5 = 1/5, so the integral of jerk^2 dt is 720 D^2 / T^5;
//   LDLJ = -ln(T^3 (8 T / (15 D))^2 720 D^2 / T^5) = -ln(64 * 720 / 225) = -ln(204.8).
const double kMinimumJerkLdlj = -std::log(204.8);

TEST(HandMetrics, MinimumJerkReachHasTheClosedFormLdljAtAnySamplingRate) {
  // Discretisation: interior third differences of a quintic err by dt^2/8 x^(5), whose weight
  // against the jerk integrates to zero (the integral of 1 - 6 s + 6 s^2 is 0). The first and
  // last jerk samples (at 1.5 dt from the ends) are held to the ends, where d(jerk^2)/dt =
  // -12 * 3600 D^2 / T^7: about 135 (dt / T)^2 relative error in the integral, i.e. in the LDLJ:
  // 2.2e-3 at 250 Hz, 1.4e-4 at 1000 Hz.
  const double at_250_hz =
      metric(hand_metrics(minimum_jerk_reach(250, 0.05)), "log_dimensionless_jerk");
  const double at_1000_hz =
      metric(hand_metrics(minimum_jerk_reach(1000, 0.05)), "log_dimensionless_jerk");
  EXPECT_NEAR(at_250_hz, kMinimumJerkLdlj, 2 * 135 * (1.0 / 250) * (1.0 / 250));
  EXPECT_NEAR(at_1000_hz, kMinimumJerkLdlj, 2 * 135 * (1.0 / 1000) * (1.0 / 1000));
  EXPECT_NEAR(at_250_hz, at_1000_hz, 2 * 135 * (1.0 / 250) * (1.0 / 250));
}

TEST(HandMetrics, LdljIsDimensionlessSoScalingTheReachChangesNothing) {
  // Positions scale by k: jerk by k, its square integral by k^2, v_peak^2 by k^2.
  const double small =
      metric(hand_metrics(minimum_jerk_reach(500, 0.01)), "log_dimensionless_jerk");
  const double large = metric(hand_metrics(minimum_jerk_reach(500, 0.3)), "log_dimensionless_jerk");
  EXPECT_NEAR(small, large, 1e-9);
}

TEST(HandMetrics, OscillationMakesAReachLessSmooth) {
  // A 0.5 mm, 5 Hz tremor on a 5 cm reach: its jerk A (2 pi f)^3 = 15.5 m/s^3 against the reach's
  // peak 60 D / T^3 = 3 m/s^3. Its squared jerk integrates to about A^2 (2 pi f)^6 T / 2 = 120
  // against 720 D^2 / T^5 = 1.8; its speed A 2 pi f = 0.016 m/s raises v_peak (0.094 m/s) by at
  // most 17%, v_peak^2 by at most 1.37. So the LDLJ drops by at least ln(67 / 1.37) = 3.9.
  const double smooth =
      metric(hand_metrics(minimum_jerk_reach(500, 0.05)), "log_dimensionless_jerk");
  const double shaky =
      metric(hand_metrics(minimum_jerk_reach(500, 0.05, 0.0005, 5)), "log_dimensionless_jerk");
  EXPECT_LT(shaky, smooth - 3.5);
}

TEST(HandMetrics, ForceIntegralsOfAConstantForce) {
  // |F| = 5 N for T = 2 s: integral F T = 10 N s, RMS and peak F.
  auto hand = sampled(2.0, 200, [](double) { return Vec{}; });
  for (auto& s : hand)
    s.force_n = {3, 0, -4};
  const auto values = hand_metrics(hand);
  EXPECT_NEAR(metric(values, "integrated_force_ns"), 10.0, 1e-12);
  EXPECT_NEAR(metric(values, "rms_force_n"), 5.0, 1e-12);
  EXPECT_DOUBLE_EQ(metric(values, "peak_force_n"), 5.0);
}

TEST(HandMetrics, ForceIntegralOfARampIsTheTrapezoid) {
  // |F| = 4 t over [0, 1]: the trapezoid rule is exact for a linear integrand: 2 N s.
  auto hand = sampled(1.0, 7, [](double) { return Vec{}; });
  for (auto& s : hand)
    s.force_n = {0, 4 * s.t_s, 0};
  EXPECT_NEAR(metric(hand_metrics(hand), "integrated_force_ns"), 2.0, 1e-12);
}

TEST(HandMetrics, JawClosuresCountCrossingsToHalfOpenOrLess) {
  // Closures at 1 -> 0.2, 0.9 -> 0.5 (0.5 counts as closed), 0.6 -> 0, 0.51 -> 0.3: four.
  const std::vector<double> jaw = {1, 0.2, 0.5, 0.9, 0.5, 0.6, 0.0, 0.51, 0.51, 0.3};
  auto hand = sampled(1.0, static_cast<int>(jaw.size()) - 1, [](double) { return Vec{}; });
  for (std::size_t i = 0; i < jaw.size(); ++i)
    hand[i].jaw = jaw[i];
  EXPECT_EQ(metric(hand_metrics(hand), "jaw_closures"), 4.0);
}

TEST(HandMetrics, RepeatedSampleTimesChangeNoMetric) {
  // Every sample of a reach recorded twice: no extra path, time or force; the derivatives use one
  // sample per time.
  const auto once = minimum_jerk_reach(400, 0.05);
  std::vector<HandSample> twice;
  for (const auto& s : once) {
    twice.push_back(s);
    twice.push_back(s);
  }
  const auto a = hand_metrics(once);
  const auto b = hand_metrics(twice);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    EXPECT_NEAR(a[i].value, b[i].value, 1e-12 * (1 + std::abs(a[i].value))) << a[i].key;
}

TEST(HandMetrics, BadInputGetsAPreciseError) {
  const auto with = [](const std::function<void(HandSample&)>& spoil) {
    auto hand = sampled(1.0, 4, [](double t) { return Vec{t, 0, 0}; });
    spoil(hand[2]);
    return error_of([&] { hand_metrics(hand); });
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(with([&](HandSample& s) { s.t_s = nan; }), "sample 2: t_s is not finite");
  EXPECT_EQ(with([&](HandSample& s) { s.tip_m[1] = inf; }), "sample 2: tip_m is not finite");
  EXPECT_EQ(with([&](HandSample& s) { s.orientation[3] = nan; }),
            "sample 2: orientation is not finite");
  EXPECT_EQ(with([&](HandSample& s) { s.jaw = -inf; }), "sample 2: jaw is not finite");
  EXPECT_EQ(with([&](HandSample& s) { s.force_n[0] = nan; }), "sample 2: force_n is not finite");
  EXPECT_EQ(with([](HandSample& s) { s.t_s = 0.125; }),
            "sample 2: t_s 0.125 is before the previous sample's 0.25");
  EXPECT_EQ(with([](HandSample& s) {
              s.orientation = {0, 0, 0, 1.5};
            }),
            "sample 2: orientation is not a unit quaternion (norm 1.5)");
  EXPECT_EQ(with([](HandSample& s) { s.jaw = 1.25; }), "sample 2: jaw 1.25 is outside [0, 1]");
  EXPECT_EQ(with([](HandSample& s) { s.jaw = -0.5; }), "sample 2: jaw -0.5 is outside [0, 1]");
  // Within the tolerance a quaternion is accepted.
  EXPECT_EQ(with([](HandSample& s) { s.orientation = {1.0005, 0, 0, 0}; }), "");
}

TEST(HandMetrics, BadThresholdsGetAPreciseError) {
  const auto with = [](const std::function<void(MotionThresholds&)>& spoil) {
    MotionThresholds th;
    spoil(th);
    return error_of([&] { hand_metrics({}, th); });
  };
  EXPECT_EQ(with([](MotionThresholds& th) { th.smoothing_s = -1; }),
            "thresholds: smoothing_s -1 is negative");
  EXPECT_EQ(
      with([](MotionThresholds& th) { th.min_idle_s = std::numeric_limits<double>::infinity(); }),
      "thresholds: min_idle_s is not finite");
  EXPECT_EQ(with([](MotionThresholds& th) {
              th.still_speed_m_s = 0.25;
              th.moving_speed_m_s = 0.125;
            }),
            "thresholds: still_speed_m_s 0.25 is above moving_speed_m_s 0.125");
}

// One hand over T = 2 s at 500 Hz, moving along y at v = 0.1 m/s while #moves(t) holds and
// standing still otherwise.
std::vector<HandSample> hand_moving_when(const std::function<bool(double)>& moves) {
  const int steps = 1000;
  const double dt = 2.0 / steps;
  std::vector<HandSample> hand(steps + 1);
  double x = 0;
  for (int i = 0; i <= steps; ++i) {
    hand[i].t_s = 2.0 * i / steps;
    if (i > 0 && moves(hand[i].t_s - 0.5 * dt)) x += 0.1 * dt;
    hand[i].tip_m = {0, x, 0};
  }
  return hand;
}

TEST(BimanualMetrics, BothHandsMovingTogetherScoresOne) {
  const auto right = hand_moving_when([](double t) { return t < 1.5; });
  const auto left = hand_moving_when([](double t) { return t < 1.5; });
  const auto values = bimanual_metrics(right, left);
  ASSERT_EQ(values.size(), 2u);
  EXPECT_EQ(values[0].key, "bimanual_dexterity");
  EXPECT_EQ(values[1].key, "path_length_ratio");
  EXPECT_EQ(metric(values, "bimanual_dexterity"), 1.0);
  EXPECT_NEAR(metric(values, "path_length_ratio"), 1.0, 1e-12);
}

TEST(BimanualMetrics, HandsMovingInAlternationScoreZero) {
  // Right moves over [0, 0.9), left over [1.1, 2]. The smoothed speeds spread each movement by at
  // most smoothing_s / 2 = 0.01 s, far less than the 0.2 s gap.
  const auto right = hand_moving_when([](double t) { return t < 0.9; });
  const auto left = hand_moving_when([](double t) { return t >= 1.1; });
  const auto values = bimanual_metrics(right, left);
  EXPECT_EQ(metric(values, "bimanual_dexterity"), 0.0);
  EXPECT_NEAR(metric(values, "path_length_ratio"), 1.0, 1e-9) << "each moved 0.9 s at v";
}

TEST(BimanualMetrics, HalfOverlapScoresAHalf) {
  // Right moves throughout [0, 2], left over [1, 2]: either moves for 2 s, both for 1 s.
  const auto right = hand_moving_when([](double) { return true; });
  const auto left = hand_moving_when([](double t) { return t >= 1; });
  const double dt = 0.002;
  const double duration = 2.0;

  // Unsmoothed, the left hand's first moving sample is the one at t = 1 (central speed v/2), which
  // stands for the time from 1 - dt/2.
  MotionThresholds raw;
  raw.smoothing_s = 0;
  const auto unsmoothed = bimanual_metrics(right, left, raw);
  EXPECT_NEAR(metric(unsmoothed, "bimanual_dexterity"), 0.5, dt / duration);
  EXPECT_NEAR(metric(unsmoothed, "path_length_ratio"), 0.5, 1e-9);

  // Smoothed over w = 2 h: the left speed averages v (t + h - 1) / (2 h) near t = 1 (the ramp
  // v/2 at t = 1 integrates like a step there), above moving_speed once t > 1 - h (1 - 2 m / v),
  // so both move for 1 + h (1 - 2 m / v), to within half a sample.
  const MotionThresholds th;
  const double h = 0.5 * th.smoothing_s;
  const double v = 0.1;
  EXPECT_NEAR(metric(bimanual_metrics(right, left, th), "bimanual_dexterity"),
              (1 + h * (1 - 2 * th.moving_speed_m_s / v)) / duration, dt / duration);
}

TEST(BimanualMetrics, NeitherHandMovingScoresZeroAndTheRatioIsUndefined) {
  const auto still = hand_moving_when([](double) { return false; });
  const auto values = bimanual_metrics(still, still);
  EXPECT_EQ(metric(values, "bimanual_dexterity"), 0.0);
  EXPECT_TRUE(std::isnan(metric(values, "path_length_ratio")));
}

TEST(BimanualMetrics, MisalignedOrBadStreamsGetAPreciseError) {
  const auto right = hand_moving_when([](double) { return true; });
  auto left = right;
  left.pop_back();
  EXPECT_EQ(error_of([&] { bimanual_metrics(right, left); }),
            "right has 1001 samples but left has 1000");
  left = right;
  left[4].t_s = 0.0075;
  EXPECT_EQ(error_of([&] { bimanual_metrics(right, left); }),
            "sample 4: left t_s 0.0075 differs from right t_s 0.008");
  left = right;
  left[0].jaw = 2;
  EXPECT_EQ(error_of([&] { bimanual_metrics(right, left); }),
            "left sample 0: jaw 2 is outside [0, 1]");
  auto bad_right = right;
  bad_right[1].tip_m[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(error_of([&] { bimanual_metrics(bad_right, right); }),
            "right sample 1: tip_m is not finite");
}

}  // namespace
}  // namespace incise::curriculum
