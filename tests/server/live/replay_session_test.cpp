// Replays: server/live/replay_session.h. A replay must land on exactly the states of the run it
// replays, whether it plays through or seeks (through its checkpoints) back and forth.
#include "server/live/replay_session.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <stdexcept>
#include <thread>

#include "test_scene.h"
#include "tests/support/wait_for.h"

namespace incise::server::live {
namespace {

using namespace std::chrono_literals;
using test::kTickS;

// 3.2 s of the script: long enough for checkpoints (every 250 ticks) to be passed and used.
constexpr std::int64_t kTicks = 1600;

using incise::test::wait_for;

TEST(ReplaySession, DurationAndSpeedBeforeStart) {
  ReplaySession replay(test::palpation_scene(), kTickS, test::scripted_records(kTicks));
  EXPECT_DOUBLE_EQ(replay.duration_s(), 3.2);
  auto status = replay.status();
  EXPECT_EQ(status["duration_s"], replay.duration_s());
  EXPECT_EQ(status["speed"], 1.0);
  // A replay opens paused on its first picture: the viewer chooses when it plays.
  EXPECT_EQ(status["state"], "paused");
  EXPECT_EQ(status["playing"], false);
  EXPECT_EQ(status["seeking"], false);
  replay.play();
  EXPECT_EQ(replay.status()["state"], "playing");
  EXPECT_FALSE(status.contains("state_hash"));

  // Clamped to [0.25, 4]; a non-finite speed means normal speed.
  const std::pair<double, double> cases[] = {
      {2.0, 2.0},
      {0.25, 0.25},
      {4.0, 4.0},
      {0.1, 0.25},
      {0.0, 0.25},
      {-3.0, 0.25},
      {4.01, 4.0},
      {1e9, 4.0},
      {std::numeric_limits<double>::infinity(), 1.0},
      {std::numeric_limits<double>::quiet_NaN(), 1.0},
  };
  for (const auto& [asked, expected] : cases) {
    replay.set_speed(asked);
    EXPECT_EQ(replay.status()["speed"], expected) << asked;
  }
  replay.pause();
  EXPECT_EQ(replay.status()["state"], "paused");
  EXPECT_EQ(replay.status()["playing"], false);

  // Before the first tick the snapshot is the scene at rest.
  const auto snapshot = replay.snapshot();
  ASSERT_NE(snapshot, nullptr);
  EXPECT_EQ(snapshot->tick, 0);
  ASSERT_NE(snapshot->surface, nullptr);
  EXPECT_EQ(snapshot->positions.rows(), 13 * 13 * 5);  // a 12 x 12 x 4 cell grid's nodes
}

TEST(ReplaySession, EmptyRecordingHasNoDuration) {
  ReplaySession replay(test::palpation_scene(), kTickS, {});
  EXPECT_EQ(replay.duration_s(), 0.0);
}

TEST(ReplaySession, BadTickThrows) {
  EXPECT_THROW(ReplaySession(test::palpation_scene(), 0.0, {}), std::invalid_argument);
  EXPECT_THROW(ReplaySession(test::palpation_scene(), -0.002, {}), std::invalid_argument);
}

// The straight run: positions after each of `ticks`, and the hash at the end.
struct StraightRun {
  std::map<std::int64_t, sim::Points> positions;
  std::string final_hash;
};

StraightRun straight_run(const sim::Scene& scene, const std::vector<TickRecord>& records,
                         std::initializer_list<std::int64_t> keep) {
  StraightRun run;
  SimEngine engine(scene, kTickS);
  for (const auto& r : records) {
    engine.tick(r.input);
    for (const auto k : keep)
      if (engine.ticks() == k) run.positions[k] = engine.positions();
  }
  run.final_hash = engine.state_hash();
  return run;
}

// Needs the replay's threads: its render thread opens an EGL display (llvmpipe when headless);
// if that fails the replay still runs and only reports a render_error.
TEST(ReplaySession, SeeksLandOnTheStraightRunsStatesBitForBit) {
  const auto scene = test::palpation_scene();
  const auto records = test::scripted_records(kTicks);
  const auto reference = straight_run(scene, records, {150, 1000, 1200, 1300, 1550, kTicks});
  EXPECT_EQ(ReplaySession::final_state_hash(scene, kTickS, records), reference.final_hash);

  ReplaySession replay(scene, kTickS, records);
  replay.start();
  replay.pause();
  auto seek_and_check = [&](double t_s, std::int64_t tick) {
    replay.seek(t_s);
    // Seeking shows as such until it lands, with where it goes.
    const auto asked = replay.status();
    if (asked["seeking"] == true) {
      EXPECT_DOUBLE_EQ(asked["seek_to_s"].get<double>(), t_s);
    }
    ASSERT_TRUE(wait_for([&] { return replay.status()["seeking"] == false; })) << "seek to " << t_s;
    EXPECT_EQ(replay.snapshot()->tick, tick) << "seek to " << t_s;
    EXPECT_NEAR(replay.status()["position_s"].get<double>(), static_cast<double>(tick) * kTickS,
                1e-9);
    const auto snapshot = replay.snapshot();
    EXPECT_DOUBLE_EQ(snapshot->sim_time_s, static_cast<double>(tick) * kTickS);
    EXPECT_TRUE(test::same_bits(snapshot->positions, reference.positions.at(tick)))
        << "seek to " << t_s;
    const auto& p = records[static_cast<std::size_t>(tick - 1)].input.position;
    EXPECT_EQ(snapshot->tool_tip, sim::Vec3(p.x, p.y, p.z));
  };
  // Checkpoints every kCheckpointTicks (250).
  seek_and_check(2.6, 1300);  // forward past several checkpoints
  seek_and_check(0.3, 150);   // back: from the checkpoint at 0
  seek_and_check(3.1, 1550);  // forward again: from the checkpoint at 1500
  seek_and_check(2.0, 1000);  // back onto a checkpoint itself
  EXPECT_EQ(replay.status()["state"], "paused");

  // Past the end clamps to the end, where the replay reports the final state's hash.
  replay.seek(100.0);
  ASSERT_TRUE(wait_for([&] { return replay.status()["state"] == "ended"; }));
  EXPECT_EQ(replay.snapshot()->tick, kTicks);
  EXPECT_EQ(replay.status()["state_hash"], reference.final_hash);

  // Back from the end, then play it out at 4x.
  seek_and_check(2.4, 1200);
  ASSERT_TRUE(wait_for([&] { return replay.status()["state"] == "paused"; }));
  replay.set_speed(4);
  replay.play();
  ASSERT_TRUE(wait_for([&] { return replay.status()["state"] == "ended"; }));
  const auto status = replay.status();
  EXPECT_EQ(status["state_hash"], reference.final_hash);
  EXPECT_EQ(status["playing"], false);
  EXPECT_EQ(status["speed"], 4.0);
  EXPECT_EQ(replay.snapshot()->tick, kTicks);
  EXPECT_TRUE(test::same_bits(replay.snapshot()->positions, reference.positions.at(kTicks)));
}

// A seek far into a long recording takes seconds of simulation; closing the replay (or seeking
// again) meanwhile must not wait for it, or the io thread that closes the viewer stalls.
TEST(ReplaySession, ALongSeekGivesWayToClosing) {
  constexpr std::int64_t kLong = 60000;  // 2 minutes of recording
  auto replay = std::make_unique<ReplaySession>(test::palpation_scene(), kTickS,
                                                test::scripted_records(kLong));
  replay->start();
  replay->seek(replay->duration_s());
  std::this_thread::sleep_for(200ms);  // well into the seek, far from its end
  const auto before = std::chrono::steady_clock::now();
  replay.reset();
  EXPECT_LT(std::chrono::steady_clock::now() - before, 500ms);
}

}  // namespace
}  // namespace incise::server::live
