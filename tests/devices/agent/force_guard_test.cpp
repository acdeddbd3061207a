// ForceGuard (devices/agent/force_guard.h): the virtual coupling against the series-spring closed
// forms, the velocity filter against its geometric closed form, the limits and the slew limit
// tick by tick, and the passivity guard's energy observer on synthetic trajectories.

#include "devices/agent/force_guard.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include <Eigen/Dense>

namespace incise::devices::agent {
namespace {

constexpr double kDt = 1e-3;  // one haptic tick [s]

using Matrix = std::array<double, 9>;

Matrix to_array(const Eigen::Matrix3d& m) {
  Matrix a;
  for (int row = 0; row < 3; ++row)
    for (int column = 0; column < 3; ++column)
      a[3 * row + column] = m(row, column);
  return a;
}

Eigen::Vector3d to_eigen(const Vec3& v) {
  return {v.x, v.y, v.z};
}

Vec3 scaled(const Vec3& v, double s) {
  return {s * v.x, s * v.y, s * v.z};
}

void expect_near(const Vec3& actual, const Vec3& expected, double tolerance) {
  EXPECT_NEAR(actual.x, expected.x, tolerance);
  EXPECT_NEAR(actual.y, expected.y, tolerance);
  EXPECT_NEAR(actual.z, expected.z, tolerance);
}

// A symmetric positive definite stiffness R diag(eigenvalues) R^T with a fixed, non-trivial R.
Eigen::Matrix3d rotated_stiffness(const Eigen::Vector3d& eigenvalues, Eigen::Matrix3d& rotation) {
  rotation = (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, -1).normalized()) *
              Eigen::AngleAxisd(-0.4, Eigen::Vector3d::UnitZ()))
                 .toRotationMatrix();
  return rotation * eigenvalues.asDiagonal() * rotation.transpose();
}

// Drives the guard's velocity estimate to (nearly) v: 200 ticks of constant velocity, after
// which the filter's lag (1 - alpha)^200 is below 1e-40.
void settle_velocity(ForceGuard& guard, const Vec3& v) {
  Vec3 x;
  for (int i = 0; i < 200; ++i) {
    guard.track(x, kDt);
    x = {x.x + v.x * kDt, x.y + v.y * kDt, x.z + v.z * kDt};
  }
}

TEST(ForceGuardCouple, WithoutModelStiffnessTheModelForcePassesUnchanged) {
  const ForceGuard guard;
  const Vec3 force{1.5, -2.25, 0.75};
  for (double age : {0.0, 0.02, 0.3}) {
    expect_near(guard.couple(force, Matrix{}, age), force, 1e-14);
  }
}

TEST(ForceGuardCouple, IsotropicStiffnessIsASeriesSpring) {
  // K = k_m I in series with k_c at a still tip: the coupling spring carries
  // k_c / (k_m + k_c) of the model's force.
  const ForceGuard guard;
  const double k_c = guard.settings().coupling_stiffness;
  const Vec3 force{3.0, -1.0, 0.5};
  for (double k_m : {10.0, 500.0, 1500.0, 20000.0, 1e5}) {
    const Matrix K{k_m, 0, 0, 0, k_m, 0, 0, 0, k_m};
    expect_near(guard.couple(force, K, 0.0), scaled(force, k_c / (k_m + k_c)), 1e-12);
  }
}

TEST(ForceGuardCouple, RenderedStiffnessIsTheSeriesStiffnessAndNeverExceedsTheCoupling) {
  // The stiffness felt at the hand, -d couple(F0 - K (x - x_ref)) / dx by finite differences,
  // is K k_c (K + k_c I)^-1: in the eigenbasis of a symmetric K, lambda k_c / (lambda + k_c).
  const ForceGuard guard;
  const double k_c = guard.settings().coupling_stiffness;
  const Vec3 f0{0.4, -0.3, 1.2};
  const Eigen::Vector3d x_ref(0.04, 0.04, 0.03);
  for (const Eigen::Vector3d& eigenvalues :
       {Eigen::Vector3d(200, 1500, 5e4), Eigen::Vector3d(0, 80, 1e5),
        Eigen::Vector3d(1e5, 1e5, 1e5)}) {
    Eigen::Matrix3d R;
    const Eigen::Matrix3d K = rotated_stiffness(eigenvalues, R);
    const auto coupled_at = [&](const Eigen::Vector3d& x) {
      const Eigen::Vector3d model = to_eigen(f0) - K * (x - x_ref);
      return to_eigen(guard.couple({model.x(), model.y(), model.z()}, to_array(K), 0.0));
    };
    const Eigen::Vector3d x0 = x_ref + Eigen::Vector3d(1e-3, -2e-3, 5e-4);
    const double h = 1e-4;
    Eigen::Matrix3d rendered;
    for (int j = 0; j < 3; ++j)
      rendered.col(j) = -(coupled_at(x0 + h * Eigen::Vector3d::Unit(j)) - coupled_at(x0)) / h;

    Eigen::Vector3d series;
    for (int i = 0; i < 3; ++i)
      series(i) = eigenvalues(i) * k_c / (eigenvalues(i) + k_c);
    const Eigen::Matrix3d expected = R * series.asDiagonal() * R.transpose();
    EXPECT_LT((rendered - expected).norm(), 1e-6 * k_c)
        << "eigenvalues " << eigenvalues.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(0.5 *
                                                                (rendered + rendered.transpose()));
    EXPECT_LT(solver.eigenvalues().maxCoeff(), k_c);
    EXPECT_GE(solver.eigenvalues().minCoeff(), -1e-6);
  }
}

TEST(ForceGuardCouple, NeverAmplifiesTheModelForceEvenForANegativeStiffness) {
  // The header promises a felt stiffness "never above k_c, whatever the server sends". A
  // protocol-valid model with a negative stiffness (|K_ij| <= 1e5 is all the decoder checks)
  // would make K + k_c I nearly singular, and k_c (K + k_c I)^-1 multiply the model force
  // (K = -0.99 k_c I would give 100 F): only the positive semidefinite part is coupled.
  const ForceGuard guard;
  const double k_c = guard.settings().coupling_stiffness;
  const Vec3 force{0.5, 0.0, 0.0};
  const double k_m = -0.99 * k_c;
  const Vec3 coupled = guard.couple(force, Matrix{k_m, 0, 0, 0, k_m, 0, 0, 0, k_m}, 0.0);
  EXPECT_LE(std::abs(coupled.x), std::abs(force.x) * (1 + 1e-12));
}

TEST(ForceGuardCouple, CouplingSoftensAsTheModelAges) {
  // At model age a the coupling is k_c / (1 + a / softening_age), seen through the series
  // formula k / (k_m + k) with K = k_m I. A negative age counts as zero.
  const ForceGuard guard;
  const ForceGuardSettings& s = guard.settings();
  const double k_m = 1000.0;
  const Matrix K{k_m, 0, 0, 0, k_m, 0, 0, 0, k_m};
  const Vec3 force{0.0, 0.0, 2.0};
  for (double age : {0.0, 0.01, 0.05, 0.1, 0.2}) {
    const double k = s.coupling_stiffness / (1.0 + age / s.softening_age_s);
    EXPECT_NEAR(guard.couple(force, K, age).z, 2.0 * k / (k_m + k), 1e-12) << age;
  }
  // Fifty ms old: half the coupling stiffness.
  const double half = 0.5 * s.coupling_stiffness;
  EXPECT_NEAR(guard.couple(force, K, 0.05).z, 2.0 * half / (k_m + half), 1e-12);
  EXPECT_EQ(guard.couple(force, K, -0.3), guard.couple(force, K, 0.0));
}

TEST(ForceGuardCouple, DampsOnlyAlongTheStiffDirection) {
  // K = k e_z e_z^T: S = K (K + k_c I)^-1 = diag(0, 0, k / (k + k_c)), so a motion along x is
  // not damped and one along z gets -b_c k / (k + k_c) v.
  const double k = 2000.0;
  const Matrix K{0, 0, 0, 0, 0, 0, 0, 0, k};
  ForceGuard along_x;
  settle_velocity(along_x, {0.2, 0.0, 0.0});
  ASSERT_NEAR(along_x.velocity().x, 0.2, 1e-9);
  EXPECT_EQ(along_x.couple({}, K, 0.0), (Vec3{}));

  ForceGuard along_z;
  settle_velocity(along_z, {0.0, 0.0, -0.15});
  const ForceGuardSettings& s = along_z.settings();
  const double v = along_z.velocity().z;
  ASSERT_NEAR(v, -0.15, 1e-9);
  const Vec3 damped = along_z.couple({}, K, 0.0);
  EXPECT_EQ(damped.x, 0.0);
  EXPECT_EQ(damped.y, 0.0);
  EXPECT_NEAR(damped.z, -s.coupling_damping * k / (k + s.coupling_stiffness) * v, 1e-12);
}

TEST(ForceGuardCouple, CouplingOffReturnsTheModelForceExactly) {
  ForceGuardSettings settings;
  settings.coupling = false;
  ForceGuard guard(settings);
  settle_velocity(guard, {0.1, 0.2, 0.3});
  const Vec3 force{1.0 / 3.0, -7.25, 0.1};
  EXPECT_EQ(guard.couple(force, Matrix{500, 1, 2, 1, 800, 3, 2, 3, 900}, 0.2), force);
}

TEST(ForceGuardTrack, VelocityFollowsTheFirstOrderLowPassClosedForm) {
  // At constant velocity v the estimate after n intervals is v (1 - (1 - alpha)^n), alpha =
  // dt / (dt + 1 / (2 pi f_c)). The first call only starts tracking and returns zero.
  ForceGuard guard;
  const double tau = 1.0 / (2.0 * std::numbers::pi * guard.settings().velocity_cutoff_hz);
  const double alpha = kDt / (kDt + tau);
  const Vec3 v{0.05, -0.1, 0.02};
  EXPECT_EQ(guard.track({0.01, 0.02, 0.03}, kDt), (Vec3{}));
  for (int n = 1; n <= 30; ++n) {
    const Vec3 x{0.01 + v.x * n * kDt, 0.02 + v.y * n * kDt, 0.03 + v.z * n * kDt};
    const Vec3 estimate = guard.track(x, kDt);
    expect_near(estimate, scaled(v, 1.0 - std::pow(1.0 - alpha, n)), 1e-12);
  }
  guard.reset();
  EXPECT_EQ(guard.velocity(), (Vec3{}));
  EXPECT_EQ(guard.track({1.0, 1.0, 1.0}, kDt), (Vec3{}));  // tracking starts afresh
}

// Limits and slew without the passivity guard in the way (a still hand injects no damping
// anyway, but this keeps each test about one thing).
ForceGuardSettings limits_only() {
  ForceGuardSettings settings;
  settings.passivity = false;
  return settings;
}

TEST(ForceGuardFinish, PerAxisLimitsClampEachAxisSeparately) {
  ForceGuardSettings settings = limits_only();
  settings.max_force_n = {1.0, 2.0, 3.0};
  settings.max_force_rate_n_s = 1e9;
  ForceGuard guard(settings);
  // Each axis is cut to its own limit; the direction is not preserved (no common scaling).
  EXPECT_EQ(guard.finish({5.0, -5.0, 2.5}, kDt), (Vec3{1.0, -2.0, 2.5}));
  EXPECT_EQ(guard.limited_ticks(), 1u);
  EXPECT_EQ(guard.finish({-0.5, 1.5, -4.0}, kDt), (Vec3{-0.5, 1.5, -3.0}));
  EXPECT_EQ(guard.limited_ticks(), 2u);
  EXPECT_EQ(guard.finish({0.25, -1.0, 2.0}, kDt), (Vec3{0.25, -1.0, 2.0}));
  EXPECT_EQ(guard.limited_ticks(), 2u);  // within the limits: not counted
}

TEST(ForceGuardFinish, SlewLimitsARisingForceButLetsItFallAtOnce) {
  ForceGuard guard(limits_only());
  const double step = guard.settings().max_force_rate_n_s * kDt;  // 1 N per tick
  // The first tick rises by one nominal tick's worth.
  EXPECT_DOUBLE_EQ(guard.finish({5.0, 0.0, -5.0}, 0.0).x, step);
  for (int n = 2; n <= 5; ++n) {
    const Vec3 f = guard.finish({5.0, 0.0, -5.0}, kDt);
    EXPECT_DOUBLE_EQ(f.x, n * step);
    EXPECT_DOUBLE_EQ(f.z, -n * step);
  }
  EXPECT_EQ(guard.finish({5.0, 0.0, -5.0}, kDt), (Vec3{5.0, 0.0, -5.0}));
  // Falling toward zero is never held back: the watchdog's fade must be felt at once.
  EXPECT_EQ(guard.finish({2.0, 0.0, -1.0}, kDt), (Vec3{2.0, 0.0, -1.0}));
  EXPECT_EQ(guard.finish({0.0, 0.0, 0.0}, kDt), (Vec3{}));
  // A change of sign drops to zero at once and rises from there, one step per tick: the old
  // direction is never held.
  guard.finish({2.0, 0.0, 0.0}, kDt);
  guard.finish({2.0, 0.0, 0.0}, kDt);
  EXPECT_DOUBLE_EQ(guard.finish({-2.0, 0.0, 0.0}, kDt).x, -step);
  EXPECT_DOUBLE_EQ(guard.finish({-2.0, 0.0, 0.0}, kDt).x, -2 * step);
  // A longer tick allows a proportionally larger step.
  EXPECT_DOUBLE_EQ(guard.finish({5.0, 0.0, 0.0}, 3 * kDt).x, 3 * step);
}

TEST(ForceGuardFinish, SilentReturnsExactlyZeroAndRestartsTheSlew) {
  ForceGuard guard;  // passivity on, with a moving hand: still no damping force when silent
  Vec3 x;
  for (int i = 0; i < 20; ++i) {
    guard.track(x, kDt);
    x.z += 1e-4;
    guard.finish({0.0, 0.0, 3.0}, kDt);
  }
  EXPECT_EQ(guard.finish({4.0, 4.0, 4.0}, kDt, /*silent=*/true), (Vec3{}));
  EXPECT_EQ(guard.last_damping(), 0.0);
  // From zero the force rises by the slew step again.
  guard.track(x, kDt);
  EXPECT_NEAR(guard.finish({4.0, 0.0, 0.0}, kDt).x, 1.0, 1e-12);
}

TEST(ForceGuardFinish, NonFiniteDesiredForceGivesZero) {
  ForceGuard guard;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(guard.finish({nan, inf, -inf}, kDt), (Vec3{}));
  // One bad axis does not take the others with it.
  EXPECT_EQ(guard.finish({nan, 0.5, 0.0}, kDt), (Vec3{0.0, 0.5, 0.0}));
}

TEST(ForceGuardFinish, TransparentSettingsReproduceTheModelForceExactly) {
  ForceGuard guard(ForceGuardSettings::transparent());
  std::mt19937 random(7);
  std::uniform_real_distribution<double> force(-90.0, 90.0);
  std::uniform_real_distribution<double> step(-2e-3, 2e-3);
  const Matrix K{400, 10, 0, 10, 900, -5, 0, -5, 3000};
  Vec3 x{0.04, 0.04, 0.03};
  for (int tick = 0; tick < 500; ++tick) {
    x = {x.x + step(random), x.y + step(random), x.z + step(random)};
    guard.track(x, kDt);
    const Vec3 model{force(random), force(random), force(random)};
    const Vec3 coupled = guard.couple(model, K, 0.1);
    ASSERT_EQ(coupled, model);
    ASSERT_EQ(guard.finish(coupled, kDt), model) << "tick " << tick;
  }
  EXPECT_EQ(guard.limited_ticks(), 0u);
  EXPECT_EQ(guard.dissipated_j(), 0.0);
}

// A hand moving along +x at speed v while the display pushes it with force F along x (F > 0:
// along the motion, so the display gives the hand F v dt each tick, which a passive virtual
// side can never do; F < 0: the hand pushes into the force and the virtual side absorbs).
struct PushingHand {
  bool started = false;
  double x = 0.0;
  double previous_force = 0.0;
  double min_energy_j = 0.0;
  double max_damping = 0.0;
  double work_on_hand_j = 0.0;  // sum of commanded force . displacement

  void run(ForceGuard& guard, double F, double v, int ticks) {
    for (int tick = 0; tick < ticks; ++tick) {
      const double dx = started ? v * kDt : 0.0;
      started = true;
      x += dx;
      work_on_hand_j += previous_force * dx;
      guard.track({x, 0.0, 0.0}, kDt);
      previous_force = guard.finish({F, 0.0, 0.0}, kDt).x;
      min_energy_j = std::min(min_energy_j, guard.energy_j());
      max_damping = std::max(max_damping, guard.last_damping());
    }
  }
};

ForceGuardSettings unlimited_rate(bool passivity) {
  ForceGuardSettings settings;
  settings.passivity = passivity;
  settings.max_force_rate_n_s = 1e9;  // the slew limit would otherwise delay the push
  return settings;
}

TEST(ForceGuardPassivity, WithoutTheGuardTheObserverCountsEveryJouleGiven) {
  // Passivity off: the observer only integrates the work of the commanded force, here
  // F (x_end - x_start), and the energy given to the hand grows without bound.
  ForceGuard guard(unlimited_rate(false));
  const double F = 2.0, v = 0.1;
  PushingHand hand;
  hand.run(guard, F, v, 1000);
  EXPECT_NEAR(hand.work_on_hand_j, F * hand.x, 1e-12);
  EXPECT_NEAR(hand.x, v * 0.999, 1e-12);
  EXPECT_NEAR(guard.energy_j(), -hand.work_on_hand_j, 1e-12);
  EXPECT_EQ(guard.dissipated_j(), 0.0);
  EXPECT_EQ(hand.max_damping, 0.0);
  hand.run(guard, F, v, 1000);
  EXPECT_NEAR(guard.energy_j(), -F * hand.x, 1e-12);
}

TEST(ForceGuardPassivity, InjectsDampingSoTheHandGetsAtMostAboutOneTicksWork) {
  ForceGuard guard(unlimited_rate(true));
  const double F = 2.0, v = 0.1;
  const double one_tick = F * v * kDt;
  PushingHand hand;
  hand.run(guard, F, v, 1000);
  // Only the velocity filter's lag in the first ticks lets more than one tick's work through
  // (the guard predicts with the estimate, which starts at zero): bound it at two ticks' work.
  // The leak only removes credit, so the work given is at most minus the observed energy.
  EXPECT_GE(hand.min_energy_j, -2.0 * one_tick);
  EXPECT_LE(hand.work_on_hand_j, 2.0 * one_tick);
  EXPECT_GT(hand.max_damping, 0.0);
  EXPECT_LE(hand.max_damping, guard.settings().max_damping);
  // The push the hand would have received (F v t = 0.2 J) went into the injected damping.
  const double dissipated = guard.dissipated_j();
  EXPECT_GT(dissipated, 0.5 * F * hand.x);
  hand.run(guard, F, v, 100);
  EXPECT_GT(guard.dissipated_j(), dissipated);
  EXPECT_GE(hand.min_energy_j, -2.0 * one_tick);
  EXPECT_LE(hand.work_on_hand_j, 2.0 * one_tick);
}

TEST(ForceGuardPassivity, TheEnergyCreditIsCappedAndThenSpentBeforeAnyDamping) {
  ForceGuard guard(unlimited_rate(true));
  const double reserve = guard.settings().energy_reserve_j;
  // The hand pushes into the force (the virtual side absorbs 2.5 mJ a tick): the credit stops
  // at the reserve.
  PushingHand hand;
  hand.run(guard, -5.0, 0.5, 200);
  EXPECT_EQ(guard.energy_j(), reserve);
  EXPECT_EQ(guard.dissipated_j(), 0.0);
  // Now the force pushes along: the credit pays for reserve / (F v) = 20 ticks of it before
  // any damping, a tick or so fewer for its leak (time constant reserve_leak_s).
  int free_ticks = 0;
  for (; free_ticks < 100; ++free_ticks) {
    hand.run(guard, 5.0, 0.5, 1);
    if (guard.last_damping() > 0.0) break;
  }
  EXPECT_GE(free_ticks, 18);
  EXPECT_LE(free_ticks, 20);
}

TEST(ForceGuardPassivity, ResetForgetsEnergyVelocityAndSlewMemory) {
  ForceGuard guard;
  PushingHand hand;
  hand.run(guard, -5.0, 0.5, 100);
  ASSERT_GT(guard.energy_j(), 0.0);
  guard.reset();
  EXPECT_EQ(guard.energy_j(), 0.0);
  EXPECT_EQ(guard.velocity(), (Vec3{}));
  EXPECT_EQ(guard.last_damping(), 0.0);
  EXPECT_DOUBLE_EQ(guard.finish({0.0, 0.0, 3.0}, kDt).z, 1.0);  // rises from zero again
}

}  // namespace
}  // namespace incise::devices::agent
