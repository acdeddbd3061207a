// The simulated hand (devices/simulated_hand.h) against the closed forms of its mass-spring-
// damper m x'' = k (g - x) - b x' + F: the underdamped step response, the static equilibrium
// g + F / k, the work of the commanded force, and independence from the polling rate.

#include "devices/simulated_hand.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace incise::devices {
namespace {

constexpr Vec3 kGoal{0.04, 0.03, 0.05};

// Holds kGoal from t = 0.
SimulatedScript still_script() {
  SimulatedScript script;
  script.waypoints = {{0.0, kGoal, 0.0}};
  return script;
}

// Starts at start and jumps to kGoal within a microsecond (less than one integration sub-step),
// then holds it: a step of the target.
SimulatedScript step_script(const Vec3& start) {
  SimulatedScript script;
  script.waypoints = {{0.0, start, 0.0}, {1e-6, kGoal, 0.0}};
  return script;
}

// Glides across 60 mm and back in a second.
SimulatedScript moving_script() {
  SimulatedScript script;
  script.waypoints = {
      {0.0, {0.0, 0.0, 0.03}, 0.0}, {0.4, {0.06, 0.02, 0.03}, 0.5}, {1.0, {0.0, 0.04, 0.01}, 0.0}};
  return script;
}

double distance(const Vec3& a, const Vec3& b) {
  return std::sqrt((a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) +
                   (a.z - b.z) * (a.z - b.z));
}

double dot(const Vec3& a, const Vec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

TEST(SimulatedHand, StepResponseMatchesTheUnderdampedClosedForm) {
  // x(t) = g + (x0 - g) e^(-zeta w t) (cos(w_d t) + zeta w / w_d sin(w_d t)),
  // w = sqrt(k / m), zeta = b / (2 sqrt(k m)), w_d = w sqrt(1 - zeta^2).
  const HandSettings settings;  // 0.15 kg, 300 N/m, 3 N s/m: zeta = 0.22
  const double m = settings.mass_kg, k = settings.grip_stiffness_n_m,
               b = settings.grip_damping_ns_m;
  const double w = std::sqrt(k / m);
  const double zeta = b / (2.0 * std::sqrt(k * m));
  const double w_d = w * std::sqrt(1.0 - zeta * zeta);
  ASSERT_LT(zeta, 1.0);
  const Vec3 start{0.03, 0.03, 0.06};  // a 10 mm step up in x, down in z
  SimulatedHand hand(step_script(start), settings);
  EXPECT_EQ(hand.poll(0.0).position, start);
  const auto closed_form = [&](double start_axis, double goal_axis, double t) {
    const double envelope = std::exp(-zeta * w * t);
    return goal_axis + (start_axis - goal_axis) * envelope *
                           (std::cos(w_d * t) + zeta * w / w_d * std::sin(w_d * t));
  };
  // Semi-implicit Euler in 0.1 ms sub-steps lags by about half a sub-step: v h / 2 = 2e-5 m at
  // the peak speed of 0.4 m/s, 0.2 % of the step.
  const double tolerance = 3e-5;
  for (int ms = 1; ms <= 600; ++ms) {
    const double t = ms * 1e-3;
    const Vec3 x = hand.poll(t).position;
    if (ms % 25 != 0) continue;
    EXPECT_NEAR(x.x, closed_form(start.x, kGoal.x, t), tolerance) << t;
    EXPECT_NEAR(x.y, kGoal.y, 1e-15) << t;  // no step in y
    EXPECT_NEAR(x.z, closed_form(start.z, kGoal.z, t), tolerance) << t;
  }
  // The first overshoot peaks at pi / w_d with e^(-zeta pi / sqrt(1 - zeta^2)) of the step.
  SimulatedHand again(step_script(start), settings);
  again.poll(0.0);
  const double peak_t = std::acos(-1.0) / w_d;
  const double overshoot = std::exp(-zeta * std::acos(-1.0) / std::sqrt(1.0 - zeta * zeta));
  EXPECT_NEAR(again.poll(peak_t).position.x - kGoal.x, overshoot * (kGoal.x - start.x), tolerance);
}

TEST(SimulatedHand, WithoutForceItSettlesOnTheTarget) {
  SimulatedHand hand(step_script({0.0, 0.0, 0.0}));
  for (int ms = 0; ms <= 3000; ++ms)
    hand.poll(ms * 1e-3);
  // e^(-zeta w t) = e^(-10 t): 1e-13 of the 64 mm step after 3 s.
  EXPECT_LT(distance(hand.poll(3.0).position, kGoal), 1e-12);
  EXPECT_LT(hand.kinetic_energy_j(), 1e-20);
  EXPECT_EQ(hand.work_on_hand_j(), 0.0);
}

TEST(SimulatedHand, AConstantForceShiftsTheRestPointByForceOverStiffness) {
  const HandSettings settings;
  SimulatedHand hand(still_script(), settings);
  const Vec3 force{1.5, -3.0, 0.6};
  hand.poll(0.0);
  hand.set_force(force);
  for (int ms = 1; ms <= 3000; ++ms)
    hand.poll(ms * 1e-3);
  const double k = settings.grip_stiffness_n_m;
  const Vec3 rest{kGoal.x + force.x / k, kGoal.y + force.y / k, kGoal.z + force.z / k};
  EXPECT_LT(distance(hand.poll(3.0).position, rest), 1e-12);
  EXPECT_EQ(hand.force(), force);
}

TEST(SimulatedHand, WorkOnHandIsTheIntegralOfForceTimesVelocity) {
  // Constant force: the work is F . (x_end - x_start), whatever the path.
  SimulatedHand hand(moving_script());
  const Vec3 force{0.8, -0.4, 1.2};
  const Vec3 start = hand.poll(0.0).position;
  hand.set_force(force);
  Vec3 end;
  for (int ms = 1; ms <= 1500; ++ms)
    end = hand.poll(ms * 1e-3).position;
  const Vec3 moved{end.x - start.x, end.y - start.y, end.z - start.z};
  EXPECT_NEAR(hand.work_on_hand_j(), dot(force, moved), 1e-12);
  EXPECT_GT(std::abs(hand.work_on_hand_j()), 1e-3);  // it did move, and the force did work

  // A force that changes at every poll: the sum of each poll's F . dx, held between polls.
  SimulatedHand varying(moving_script());
  Vec3 x = varying.poll(0.0).position;
  double expected = 0.0;
  for (int ms = 1; ms <= 1000; ++ms) {
    const double phase = ms * 0.013;
    const Vec3 f{std::sin(phase), std::cos(2 * phase), -0.5 * std::sin(3 * phase)};
    varying.set_force(f);
    const Vec3 next = varying.poll(ms * 1e-3).position;
    expected += dot(f, {next.x - x.x, next.y - x.y, next.z - x.z});
    x = next;
  }
  EXPECT_NEAR(varying.work_on_hand_j(), expected, 1e-12);
}

TEST(SimulatedHand, ThePollingRateDoesNotChangeTheMotion) {
  // Every poll integrates in sub-steps of at most 0.1 ms, so 1 kHz, 250 Hz and an irregular
  // rate all follow the same trajectory up to integration error: the semi-implicit lag behind
  // the moving target is about v h / 2 (7.5 um at 0.15 m/s), and the sub-steps differ by up to
  // 10 % between rates (rounding makes ceil(1 ms / 0.1 ms) 11 on some polls), so about 1 um.
  const Vec3 force{0.3, 0.0, -0.7};
  SimulatedHand fast(moving_script());
  SimulatedHand slow(moving_script());
  SimulatedHand irregular(moving_script());
  for (SimulatedHand* hand : {&fast, &slow, &irregular}) {
    hand->poll(0.0);
    hand->set_force(force);
  }
  double t_irregular = 0.0;
  int k = 0;
  for (int ms = 1; ms <= 1200; ++ms) {
    const double t = ms * 1e-3;
    const Vec3 a = fast.poll(t).position;
    if (ms % 4 != 0) continue;
    const Vec3 b = slow.poll(t).position;
    // Steps of 0.3 .. 2.7 ms up to t, then t itself.
    for (double next = t_irregular + 3e-4 * (1 + k++ % 9); next < t;
         next = t_irregular + 3e-4 * (1 + k++ % 9)) {
      irregular.poll(next);
      t_irregular = next;
    }
    t_irregular = t;
    const Vec3 c = irregular.poll(t).position;
    EXPECT_LT(distance(a, b), 3e-6) << t;
    EXPECT_LT(distance(a, c), 3e-6) << t;
  }
  EXPECT_NEAR(fast.work_on_hand_j(), slow.work_on_hand_j(), 1e-8);
  EXPECT_NEAR(fast.work_on_hand_j(), irregular.work_on_hand_j(), 1e-8);
  EXPECT_GT(fast.work_on_hand_j(), 1e-3);
}

TEST(SimulatedHand, ReportsTheScriptsJawAndForceOutput) {
  SimulatedHand hand(moving_script());
  EXPECT_TRUE(hand.capabilities().has_force_output);
  EXPECT_EQ(hand.degrees_of_freedom(), 7);
  EXPECT_EQ(hand.name(), "simulated hand");
  hand.poll(0.0);
  EXPECT_FLOAT_EQ(hand.poll(0.2).jaw, 0.25f);  // halfway to the 0.5 at 0.4 s
  EXPECT_EQ(hand.target_at(0.4).position, (Vec3{0.06, 0.02, 0.03}));
  const double v = std::sqrt(dot(hand.velocity(), hand.velocity()));
  EXPECT_NEAR(hand.kinetic_energy_j(), 0.5 * HandSettings{}.mass_kg * v * v, 1e-18);
}

TEST(SimulatedHand, BadSettingsThrow) {
  const auto make = [](HandSettings settings) { SimulatedHand hand(still_script(), settings); };
  const char* expected = "simulated hand: mass and grip stiffness must be > 0, damping >= 0";
  for (HandSettings bad :
       {HandSettings{0.0, 300, 3}, HandSettings{-0.1, 300, 3}, HandSettings{0.15, 0.0, 3},
        HandSettings{0.15, 300, -1.0}, HandSettings{std::nan(""), 300, 3},
        HandSettings{0.15, 300, std::nan("")}}) {
    try {
      make(bad);
      ADD_FAILURE() << "no throw for mass " << bad.mass_kg << ", k " << bad.grip_stiffness_n_m
                    << ", b " << bad.grip_damping_ns_m;
    } catch (const std::invalid_argument& e) {
      EXPECT_STREQ(e.what(), expected);
    }
  }
  EXPECT_NO_THROW(make(HandSettings{0.15, 300, 0.0}));                    // no damping is allowed
  EXPECT_THROW(SimulatedHand{SimulatedScript{}}, std::invalid_argument);  // no waypoints
}

}  // namespace
}  // namespace incise::devices
