// Evaluating the local force model and fading it: devices/agent/force_model_evaluator.h,
// devices/agent/force_fade.h.

#include "devices/agent/force_model_evaluator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "devices/agent/force_fade.h"

namespace incise::devices::agent {
namespace {

using namespace std::chrono_literals;

double norm(const Vec3& v) {
  return std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
}

TEST(ForceModelEvaluator, IsForceMinusStiffnessTimesDisplacement) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> metres(-0.005, 0.005);
  std::uniform_real_distribution<double> newtons(-3.0, 3.0);
  std::uniform_real_distribution<double> stiffness(-800.0, 800.0);
  ForceModelEvaluator evaluator;
  for (int i = 0; i < 500; ++i) {
    ForceModel m;
    m.reference_position = {0.04 + metres(rng), 0.04 + metres(rng), 0.03 + metres(rng)};
    m.force = {newtons(rng), newtons(rng), newtons(rng)};
    for (double& k : m.stiffness)
      k = stiffness(rng);
    evaluator.set_model(m, Clock::time_point{});
    const Vec3 x = {m.reference_position.x + metres(rng), m.reference_position.y + metres(rng),
                    m.reference_position.z + metres(rng)};
    // The closed form, row by row: F_r = F0_r - sum_c K_rc (x_c - x0_c).
    const double dx[3] = {x.x - m.reference_position.x, x.y - m.reference_position.y,
                          x.z - m.reference_position.z};
    const double f0[3] = {m.force.x, m.force.y, m.force.z};
    double expected[3];
    for (int r = 0; r < 3; ++r) {
      expected[r] = f0[r];
      for (int c = 0; c < 3; ++c)
        expected[r] -= m.stiffness[3 * r + c] * dx[c];
    }
    const Vec3 f = evaluator.force_at(x);
    EXPECT_NEAR(f.x, expected[0], 1e-12);
    EXPECT_NEAR(f.y, expected[1], 1e-12);
    EXPECT_NEAR(f.z, expected[2], 1e-12);
    EXPECT_EQ(evaluator.force_at(m.reference_position), m.force);  // exactly F0 at x0
  }
}

TEST(ForceModelEvaluator, FarFromTheReferenceTheForceIsCappedNotTurned) {
  ForceModel m;
  m.force = {0.0, 0.0, 2.0};
  m.stiffness = {1e4, 0, 0, 0, 1e4, 0, 0, 0, 1e4};
  ForceModelEvaluator evaluator;
  evaluator.set_model(m, Clock::time_point{});
  const Vec3 x = {-0.03, 0.04, -0.05};  // unclamped: (300, -400, 502) N
  const Vec3 f = evaluator.force_at(x);
  EXPECT_NEAR(norm(f), kMaxModelForce, 1e-9);
  const double scale = kMaxModelForce / std::sqrt(300.0 * 300 + 400.0 * 400 + 502.0 * 502);
  EXPECT_NEAR(f.x, 300.0 * scale, 1e-9);
  EXPECT_NEAR(f.y, -400.0 * scale, 1e-9);
  EXPECT_NEAR(f.z, 502.0 * scale, 1e-9);
}

TEST(ForceModelEvaluator, NoModelNoForceAndFreshnessEndsFifteenMsAfterTheLastModel) {
  ForceModelEvaluator evaluator;
  const Clock::time_point t0 = Clock::now();
  EXPECT_FALSE(evaluator.has_model());
  EXPECT_EQ(evaluator.force_at({1, 2, 3}), (Vec3{}));
  EXPECT_FALSE(evaluator.fresh(t0));
  ForceModel m;
  m.force = {1, 0, 0};
  evaluator.set_model(m, t0);
  EXPECT_TRUE(evaluator.fresh(t0));
  EXPECT_TRUE(evaluator.fresh(t0 + 15ms));
  EXPECT_FALSE(evaluator.fresh(t0 + 15ms + 1ns));
  // The age counts from the state the model answers, on the agent's clock.
  m.state_timestamp_us = 5000;
  evaluator.set_model(m, t0);
  EXPECT_EQ(evaluator.age_us(305'000), 300'000u);
  EXPECT_EQ(evaluator.age_us(4000), 0u);  // an echo from the future reads as new
  evaluator.clear();
  EXPECT_FALSE(evaluator.fresh(t0));
}

TEST(ForceFade, RampsByATenthPerTickToExactlyZeroAndOne) {
  ForceFade fade;
  EXPECT_EQ(fade.factor(), 0.0);  // silent until a model fades in
  for (int i = 1; i <= 10; ++i)
    EXPECT_EQ(fade.step(true), i / 10.0);
  EXPECT_EQ(fade.step(true), 1.0);
  for (int i = 9; i >= 0; --i)
    EXPECT_EQ(fade.step(false), i / 10.0);
  EXPECT_EQ(fade.factor(), 0.0);
  EXPECT_EQ(fade.step(false), 0.0);
  // A flicker moves one step at a time either way.
  EXPECT_EQ(fade.step(true), 0.1);
  EXPECT_EQ(fade.step(false), 0.0);
}

}  // namespace
}  // namespace incise::devices::agent
