// Tests of sim/tools/cutting_resistance.h: the closed forms (toughness x depth against the motion
// across the edge at speed, nothing at zero depth or speed or along the edge, the linear ramp
// below ramp_speed, the cap), passivity for any input, and the work over a stroke: the toughness
// times the area cut.

#include "sim/tools/cutting_resistance.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

namespace incise::sim::tools {
namespace {

void expect_near(const Vec3& a, const Vec3& b, Real tolerance) {
  EXPECT_LT((a - b).norm(), tolerance) << a.transpose() << " vs " << b.transpose();
}

TEST(CuttingResistance, AtSpeedItIsToughnessTimesDepthAgainstTheMotion) {
  // An upright blade drawn sideways: G depth, straight back.
  expect_near(cutting_resistance(200, 0.006, Vec3(0.1, 0, 0), Vec3(0, 0, -1)), Vec3(-1.2, 0, 0),
              1e-15);
  expect_near(cutting_resistance(500, 0.003, Vec3(0, -0.05, 0), Vec3(0, 0, 1)), Vec3(0, 1.5, 0),
              1e-15);
  // Any edge, any motion across it: |F| = G depth, F = -|F| v / |v|.
  const Vec3 edge = Vec3(1, 1, 1).normalized();
  const Vec3 across = Vec3(1, -1, 0).normalized();
  for (const Real speed : {0.02, 0.3, 2.0}) {
    const Vec3 v = speed * across;
    const Vec3 f = cutting_resistance(350, 0.008, v, edge);
    EXPECT_NEAR(f.norm(), 350 * 0.008, 1e-13);
    expect_near(f, -2.8 * across, 1e-13);
  }
}

TEST(CuttingResistance, NoDepthNoToughnessOrNoMotionMeansNoForce) {
  const Vec3 e(0, 0, -1), v(0.1, 0.05, 0);
  EXPECT_EQ(cutting_resistance(200, 0, v, e), Vec3::Zero());
  EXPECT_EQ(cutting_resistance(0, 0.01, v, e), Vec3::Zero());
  EXPECT_EQ(cutting_resistance(200, 0.01, Vec3::Zero(), e), Vec3::Zero());
}

// Motion along the edge opens no new surface: a blade pushed in point first or drawn out along
// its axis is not held back; of an oblique motion only the part across the edge is.
TEST(CuttingResistance, MotionAlongTheEdgeOpensNoSurfaceAndMeetsNoResistance) {
  const Vec3 e = Vec3(0.2, -0.3, 1).normalized();
  // (To rounding: the ramp divides the velocity's rounding across the edge by v0.)
  EXPECT_LT(cutting_resistance(200, 0.01, 0.3 * e, e).norm(), 1e-12);
  EXPECT_LT(cutting_resistance(200, 0.01, -0.3 * e, e).norm(), 1e-12);
  const Vec3 n = e.cross(Vec3::UnitX()).normalized();  // across the edge
  const Vec3 f = cutting_resistance(200, 0.01, 0.5 * e + 0.1 * n, e);
  expect_near(f, -2.0 * n, 1e-14);
  EXPECT_NEAR(f.dot(e), 0, 1e-15);
  EXPECT_LE(f.dot(0.5 * e + 0.1 * n), 0);
}

TEST(CuttingResistance, BelowTheRampSpeedTheForceFadesLinearlyToZero) {
  const Vec3 e(0, 0, 1);
  CuttingResistanceSettings settings;
  settings.ramp_speed = 0.01;
  const Real full = 300 * 0.004;  // 1.2 N
  for (const Real speed : {1e-6, 0.002, 0.005, 0.0099}) {
    const Vec3 f = cutting_resistance(300, 0.004, Vec3(speed, 0, 0), e, settings);
    expect_near(f, Vec3(-full * speed / 0.01, 0, 0), 1e-15);
    // Odd in the velocity: no jump where the motion reverses, so nothing to chatter.
    EXPECT_EQ(cutting_resistance(300, 0.004, Vec3(-speed, 0, 0), e, settings), -f);
  }
  // Continuous at the ramp speed, full above it.
  const Real below = cutting_resistance(300, 0.004, Vec3(0.01 * (1 - 1e-9), 0, 0), e).norm();
  const Real above = cutting_resistance(300, 0.004, Vec3(0.01 * (1 + 1e-9), 0, 0), e).norm();
  EXPECT_NEAR(below, full, 1e-8);
  EXPECT_EQ(above, full);
  // A slower ramp moves the knee: at 0.02 m/s, half of it against 0.04.
  settings.ramp_speed = 0.04;
  EXPECT_NEAR(cutting_resistance(300, 0.004, Vec3(0, 0.02, 0), e, settings).norm(), full / 2,
              1e-15);
}

TEST(CuttingResistance, ItIsCappedAtMaxForce) {
  const Vec3 e(0, 0, -1), v(0, 0.2, 0);
  expect_near(cutting_resistance(1000, 0.02, v, e), Vec3(0, -4, 0), 1e-15);  // 20 N, capped at 4
  CuttingResistanceSettings settings;
  settings.max_force = 2.5;
  expect_near(cutting_resistance(1000, 0.02, v, e, settings), Vec3(0, -2.5, 0), 1e-15);
  expect_near(cutting_resistance(100, 0.02, v, e, settings), Vec3(0, -2, 0), 1e-15);  // below
  // The cap and the ramp together: a quarter of the cap at a quarter of the ramp speed.
  expect_near(cutting_resistance(1000, 0.02, Vec3(0.0025, 0, 0), e, settings), Vec3(-0.625, 0, 0),
              1e-15);
}

// F . v <= 0 whatever the inputs (to rounding: v nearly along the edge leaves a w of rounding
// size), and F . v = -min(G depth, cap) |w|^2 / max(|w|, v0) with w the velocity across the edge:
// the power the tissue takes.
TEST(CuttingResistance, IsPassiveForAnyInput) {
  std::mt19937 random(2024);
  std::uniform_real_distribution<Real> unit(-1, 1), toughness(0, 5000), depth(0, 0.05),
      decade(-5, 1);
  const CuttingResistanceSettings settings;
  for (int k = 0; k < 20000; ++k) {
    const Vec3 e = Vec3(unit(random), unit(random), unit(random)).normalized();
    Vec3 v = Vec3(unit(random), unit(random), unit(random)) * std::pow(10, decade(random));
    if (k % 7 == 0) v = 0.2 * e + 1e-7 * v;  // nearly along the edge
    const Real g = toughness(random), d = depth(random);
    const Vec3 f = cutting_resistance(g, d, v, e, settings);
    const Vec3 w = v - v.dot(e) * e;
    const Real power = -std::min(g * d, settings.max_force) * w.squaredNorm() /
                       std::max(w.norm(), settings.ramp_speed);
    ASSERT_LE(f.dot(v), 1e-15 * f.norm() * v.norm()) << "k = " << k;
    ASSERT_NEAR(f.dot(v), power, 1e-12 * std::max(Real(1), std::abs(power))) << "k = " << k;
  }
}

// A blade drawn straight at 5 cm/s while its depth grows linearly from 0 to D over the stroke's
// length L: the hand's work is -G times the area cut, -G D L / 2 (midpoint depths over each step
// integrate a linear depth exactly).
TEST(CuttingResistance, TheWorkOverAStrokeIsTheToughnessTimesTheAreaCut) {
  const Real g = 180, depth = 0.008, length = 0.04, speed = 0.05, dt = 1e-4;
  const Vec3 e(0, 0, -1), along(0, 1, 0);
  const int steps = static_cast<int>(std::lround(length / (speed * dt)));
  Real work = 0;
  for (int n = 0; n < steps; ++n) {
    const Real d = depth * (n + 0.5) / steps;
    const Vec3 dx = speed * dt * along;
    work += cutting_resistance(g, d, dx / dt, e).dot(dx);
  }
  EXPECT_NEAR(work, -g * depth * length / 2, 1e-12);
}

TEST(CuttingResistance, BadInputsAreRefused) {
  const Vec3 e(0, 0, 1), v(0.1, 0, 0);
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  const Real inf = std::numeric_limits<Real>::infinity();
  EXPECT_THROW(cutting_resistance(-1, 0.01, v, e), std::invalid_argument);
  EXPECT_THROW(cutting_resistance(inf, 0.01, v, e), std::invalid_argument);
  EXPECT_THROW(cutting_resistance(200, -0.001, v, e), std::invalid_argument);
  EXPECT_THROW(cutting_resistance(200, nan, v, e), std::invalid_argument);
  EXPECT_THROW(cutting_resistance(200, 0.01, Vec3(inf, 0, 0), e), std::invalid_argument);
  EXPECT_THROW(cutting_resistance(200, 0.01, v, Vec3(0, 0, 2)), std::invalid_argument);
  EXPECT_THROW(cutting_resistance(200, 0.01, v, Vec3::Zero()), std::invalid_argument);
  CuttingResistanceSettings settings;
  settings.ramp_speed = 0;
  EXPECT_THROW(cutting_resistance(200, 0.01, v, e, settings), std::invalid_argument);
  settings = {};
  settings.max_force = -1;
  EXPECT_THROW(cutting_resistance(200, 0.01, v, e, settings), std::invalid_argument);
}

}  // namespace
}  // namespace incise::sim::tools
