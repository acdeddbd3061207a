// Falling behind real time and recovering: server/live/pace_monitor.h, on scripted clocks.
#include "server/live/pace_monitor.h"

#include <gtest/gtest.h>

#include <string>

namespace incise::server::live {
namespace {

constexpr double kTickS = 0.002;

// Ticks from t for `seconds` at `speed` times real time (each tick ends kTickS / speed after the
// last), starting each tick `lag_s` late. Returns the wall time after the last.
double run(PaceMonitor& pace, double t, double seconds, double speed, double lag_s = 0) {
  const double period = kTickS / speed;
  for (double end = t + seconds; t + period <= end + 1e-12;) {
    t += period;
    pace.on_tick(t, lag_s);
  }
  return t;
}

TEST(PaceMonitor, KeepingUpIsNotBehindAndShedsNothing) {
  PaceMonitor pace(kTickS);
  pace.restart(100);
  const double t = run(pace, 100, 3, 1.0);
  const PaceState s = pace.state_at(t);
  EXPECT_FALSE(s.behind);
  EXPECT_NEAR(s.real_time_factor, 1.0, 1e-6);
  EXPECT_EQ(s.lag_s, 0);
  EXPECT_EQ(s.shed_level, 0);
  EXPECT_EQ(ShedPlan{}.text(s.shed_level), "");
  EXPECT_EQ(ShedPlan{}.render_divisor(s.shed_level), 1);
}

TEST(PaceMonitor, HalfSpeedIsBehindWithItsFactorAndShedsLevelByLevelUpToTheLast) {
  PaceMonitor pace(kTickS);
  pace.restart(0);
  double t = run(pace, 0, 0.55, 0.5);  // one window
  PaceState s = pace.state_at(t);
  EXPECT_TRUE(s.behind);
  EXPECT_NEAR(s.real_time_factor, 0.5, 0.01);
  EXPECT_EQ(s.shed_level, 1);
  t = run(pace, t, 3, 0.5);
  s = pace.state_at(t);
  EXPECT_EQ(s.shed_level, kRenderShedLevels);  // never beyond the last level
}

TEST(PaceMonitor, ASceneWithAdaptivityShedsItsRemeshingFirstThenThePicture) {
  const ShedPlan plan{2};
  EXPECT_EQ(plan.max_level(), 4);
  const int physics[] = {0, 1, 2, 2, 2};
  const int divisor[] = {1, 1, 1, 2, 4};
  const char* text[] = {"", "refinement paused", "refinement paused, refined tissue coarsened",
                        "refinement paused, refined tissue coarsened, render rate halved",
                        "refinement paused, refined tissue coarsened, render rate quartered"};
  for (int level = 0; level <= 4; ++level) {
    EXPECT_EQ(plan.physics_level(level), physics[level]) << level;
    EXPECT_EQ(plan.render_divisor(level), divisor[level]) << level;
    EXPECT_EQ(plan.text(level), text[level]) << level;
  }
  // Without adaptivity only the picture is shed.
  const ShedPlan picture_only;
  EXPECT_EQ(picture_only.max_level(), 2);
  EXPECT_EQ(picture_only.physics_level(2), 0);
  EXPECT_EQ(picture_only.text(1), "render rate halved");
  EXPECT_EQ(picture_only.render_divisor(2), 4);
  // The monitor climbs to the plan's last level and no further.
  PaceMonitor pace(kTickS, plan.max_level());
  pace.restart(0);
  const double t = run(pace, 0, 4, 0.5);
  EXPECT_EQ(pace.state_at(t).shed_level, 4);
}

TEST(PaceMonitor, RecoversAfterKeepingUpAndGivesTheLevelsBackOneAtATime) {
  PaceSettings settings;
  PaceMonitor pace(kTickS, kRenderShedLevels, settings);
  pace.restart(0);
  double t = run(pace, 0, 2, 0.5);
  ASSERT_TRUE(pace.state_at(t).behind);
  ASSERT_EQ(pace.state_at(t).shed_level, 2);
  // Kept up for less than recover_s: still behind, nothing given back.
  t = run(pace, t, settings.recover_s - 2 * settings.window_s, 1.0);
  EXPECT_TRUE(pace.state_at(t).behind);
  EXPECT_EQ(pace.state_at(t).shed_level, 2);
  // recover_s kept up: keeping up, one level back; another recover_s: the next.
  t = run(pace, t, 2 * settings.window_s + 0.1, 1.0);
  EXPECT_FALSE(pace.state_at(t).behind);
  EXPECT_EQ(pace.state_at(t).shed_level, 1);
  t = run(pace, t, settings.recover_s + 0.1, 1.0);
  EXPECT_EQ(pace.state_at(t).shed_level, 0);
  EXPECT_NEAR(pace.state_at(t).real_time_factor, 1.0, 1e-6);
}

TEST(PaceMonitor, ALevelNotEnoughComesStraightBack) {
  PaceMonitor pace(kTickS);
  pace.restart(0);
  double t = run(pace, 0, 0.55, 0.5);
  ASSERT_EQ(pace.state_at(t).shed_level, 1);
  t = run(pace, t, 3, 1.0);  // recovered: level 0
  ASSERT_EQ(pace.state_at(t).shed_level, 0);
  t = run(pace, t, 0.55, 0.8);  // too slow again at level 0
  EXPECT_TRUE(pace.state_at(t).behind);
  EXPECT_EQ(pace.state_at(t).shed_level, 1);
}

TEST(PaceMonitor, ScheduleLagAloneIsBehind) {
  // Full speed but each tick starts 80 ms late (a backlog it works off at 1x): behind, by that.
  PaceMonitor pace(kTickS);
  pace.restart(0);
  const double t = run(pace, 0, 0.6, 1.0, 0.08);
  const PaceState s = pace.state_at(t);
  EXPECT_TRUE(s.behind);
  EXPECT_DOUBLE_EQ(s.lag_s, 0.08);
}

TEST(PaceMonitor, ATickThatHangsShowsAsGrowingLagUntilTheNextOneEnds) {
  PaceMonitor pace(kTickS);
  pace.restart(0);
  double t = run(pace, 0, 1, 1.0);
  ASSERT_FALSE(pace.state_at(t).behind);
  // No tick ends for 3 s: 3 s behind (less the one tick's own time), and the factor drops.
  PaceState s = pace.state_at(t + 3);
  EXPECT_TRUE(s.behind);
  EXPECT_NEAR(s.lag_s, 3 - kTickS, 1e-9);
  EXPECT_LT(s.real_time_factor, 0.2);
  // Below the threshold a pause between ticks is nothing.
  EXPECT_FALSE(pace.state_at(t + 0.01).behind);
  // The hung tick ends; the window that held it is behind, and the monitor says so.
  pace.on_tick(t + 3, 0);
  t = t + 3;
  s = pace.state_at(t);
  EXPECT_TRUE(s.behind);
  EXPECT_GE(s.shed_level, 1);
}

TEST(PaceMonitor, ARestartForgetsTheGapButKeepsTheLevel) {
  PaceMonitor pace(kTickS);
  pace.restart(0);
  double t = run(pace, 0, 0.55, 0.5);
  ASSERT_EQ(pace.state_at(t).shed_level, 1);
  // A pause of a minute, then the schedule restarts: no stall from the pause.
  pace.restart(t + 60);
  EXPECT_EQ(pace.state_at(t + 60.001).lag_s, 0);
  EXPECT_EQ(pace.state_at(t + 60.001).shed_level, 1);
}

}  // namespace
}  // namespace incise::server::live
