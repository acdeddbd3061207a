// The passivity guard against a stiff wall behind a delayed, lossy link (delayed_wall.h), in
// simulated time: a simulated hand taps the wall once a second for 20 s. A delayed model makes
// the wall push back later and longer than it was pushed, so without the guard every tap gives
// the hand energy; with it the device never gives back more than it took.

#include <gtest/gtest.h>

#include "delayed_wall.h"

namespace incise::devices::agent::testing {
namespace {

constexpr double kSeconds = 20.0;

WallLinkSettings link_with(int delay_ms, double loss = 0.0) {
  WallLinkSettings link;
  link.delay = std::chrono::milliseconds(delay_ms);
  link.loss = loss;
  return link;
}

ForceGuardSettings with_passivity(bool on) {
  ForceGuardSettings guard;
  guard.passivity = on;
  return guard;
}

TEST(PassivityGuard, WithoutItAHundredMsDelayGivesTheHandEnergyEveryTap) {
  const WallRun run = run_wall(link_with(100), with_passivity(false), kSeconds);
  // Energy flows into the hand, and keeps flowing: the second ten taps give as much as the first.
  EXPECT_GT(run.work_on_hand_j, 0.02);
  const double second_half = run.work_on_hand_j - run.work_first_half_j;
  EXPECT_GT(run.work_first_half_j, 0.01);
  EXPECT_GT(second_half, 0.8 * run.work_first_half_j);
}

TEST(PassivityGuard, KeepsTheWallPassiveAtEveryDelayAndAtFivePercentLoss) {
  for (int delay_ms : {0, 10, 25, 50, 100}) {
    for (double loss : {0.0, 0.05}) {
      SCOPED_TRACE(::testing::Message() << delay_ms << " ms, loss " << loss);
      const WallRun run = run_wall(link_with(delay_ms, loss), with_passivity(true), kSeconds);
      // The device never gives the hand more energy than the hand gave the wall.
      EXPECT_LE(run.work_on_hand_j, 0.0);
      EXPECT_LE(run.work_on_hand_j - run.work_first_half_j, 0.0);
      // Stable contact: no bounce away faster than the hand moves by itself (the script moves
      // 20 mm in 0.5 s, 0.04 m/s), the tip stays within the 10 mm the hand reaches for, and
      // the force stays within the device's limits.
      EXPECT_LT(run.max_speed_m_s, 0.3);
      EXPECT_LT(run.peak_depth_m, 0.0101);
      EXPECT_LE(run.peak_force_n, 8.0 + 1e-12);
      EXPECT_GT(run.peak_force_n, 1.0);  // it did touch the wall
    }
  }
}

TEST(PassivityGuard, AtZeroDelayItBarelyChangesTheWall) {
  const WallRun plain = run_wall(link_with(0), with_passivity(false), kSeconds);
  const WallRun guarded = run_wall(link_with(0), with_passivity(true), kSeconds);
  // Without delay the loop renders the coupled wall closely either way: RMS error under 10 %
  // of the peak force, and the same peak within 5 %.
  EXPECT_LT(plain.rms_force_error_n, 0.1 * plain.peak_force_n);
  EXPECT_LT(guarded.rms_force_error_n, 0.1 * guarded.peak_force_n);
  EXPECT_NEAR(guarded.peak_force_n, plain.peak_force_n, 0.05 * plain.peak_force_n);
}

TEST(PassivityGuard, TheCouplingSoftensTheWallAsTheModelAges) {
  // The rendered stiffness falls with the model's age: at 100 ms each way (200 ms old) the
  // coupling is a fifth of k_c, so the same tap goes deeper than at 10 ms.
  const WallRun fresh = run_wall(link_with(10), with_passivity(true), kSeconds);
  const WallRun old = run_wall(link_with(100), with_passivity(true), kSeconds);
  EXPECT_GT(old.peak_depth_m, fresh.peak_depth_m);
}

}  // namespace
}  // namespace incise::devices::agent::testing
