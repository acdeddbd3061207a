// Scoring a recorded session: server/live/scoring.h, on a real migrated SQLite file.
#include "server/live/scoring.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "curriculum/metric_catalogue.h"
#include "db/database.h"
#include "db/migrations.h"
#include "db/recordings_repo.h"
#include "db/training_repo.h"
#include "db/users_repo.h"
#include "tests/support/temp_dir.h"

namespace incise::server::live {
namespace {

constexpr double kTickS = 0.002;
constexpr std::int64_t kNow = 1894003200;

// A wandering probe: ticks from `first`, positions and forces that change every tick.
std::vector<TickRecord> wandering_records(std::uint32_t first, std::uint32_t count,
                                          std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> step(-1e-3, 1e-3);
  std::uniform_real_distribution<float> force(-2.0f, 2.0f);
  std::vector<TickRecord> records(count);
  double x = 0.04, y = 0.04, z = 0.04;
  for (std::uint32_t i = 0; i < count; ++i) {
    auto& r = records[i];
    r.tick = first + i;
    x += step(rng);
    y += step(rng);
    z += step(rng);
    r.input.position = {x, y, z};
    for (float& f : r.force)
      f = force(rng);
  }
  return records;
}

// The catalogue (curriculum/metric_catalogue.h) and what scoring reports cannot drift apart: a
// two-handed recording with a portal reports every metric there is, each in the catalogue with
// the catalogue's unit, and every row of the catalogue is reported.
TEST(MetricCatalogue, EveryReportedMetricIsCataloguedWithItsUnitAndEveryRowIsReported) {
  auto records = wandering_records(0, 300, 7);
  for (auto& r : records) {
    r.has_second = true;
    r.second.input = r.input;
    r.second.input.position.y += 0.05f;
  }
  curriculum::Task task;
  task.portal_m = std::array<double, 3>{0, 0, 0};
  auto values = session_metrics(records, kTickS, task);
  for (const auto& v : simulation_metrics({}))
    values.push_back(v);
  std::set<std::string> reported;
  for (const auto& v : values) {
    reported.insert(v.key);
    const auto info = curriculum::find_metric(v.key);
    ASSERT_TRUE(info) << v.key << " is not in the catalogue";
    EXPECT_EQ(info->unit, v.unit) << v.key;
  }
  for (const auto& info : curriculum::metric_catalogue()) {
    EXPECT_TRUE(reported.contains(info.key)) << info.key << " is catalogued but never reported";
    EXPECT_FALSE(info.name.empty());
    EXPECT_FALSE(info.definition.empty());
    EXPECT_GT(info.display_scale, 0);
  }
}

TEST(ToolSamples, MapTicksPositionsAndForcesExactly) {
  const auto records = wandering_records(17, 500, 1);
  const auto samples = tool_samples(records, kTickS);
  ASSERT_EQ(samples.size(), records.size());
  for (std::size_t i = 0; i < records.size(); ++i) {
    const auto& r = records[i];
    const auto& s = samples[i];
    EXPECT_EQ(s.t_s, static_cast<double>(r.tick) * kTickS);
    EXPECT_EQ(s.tip_m[0], r.input.position.x);
    EXPECT_EQ(s.tip_m[1], r.input.position.y);
    EXPECT_EQ(s.tip_m[2], r.input.position.z);
    for (int k = 0; k < 3; ++k)  // a float widens to a double exactly
      EXPECT_EQ(s.force_n[static_cast<std::size_t>(k)], static_cast<double>(r.force[k]));
  }
  EXPECT_TRUE(tool_samples({}, kTickS).empty());
}

class ScoreSession : public ::testing::Test {
 protected:
  void SetUp() override {
    db::apply_migrations(db_);
    trainee_ = db::UsersRepo(db_)
                   .create({"tess", "Tess Trainee", db::Role::trainee, "a long password"}, kNow)
                   .id;
    session_ = db::TrainingRepo(db_).create_session(trainee_, std::nullopt, "palpation", kNow);
    recording_ = recordings_.create(session_, "scenes/palpation.json", "0123456789abcdef", 0,
                                    1 / kTickS, kNow);
  }

  // Appends records as chunks of `per_chunk` ticks, as the live session's recorder does.
  void record(const std::vector<TickRecord>& records, std::size_t per_chunk) {
    for (std::size_t at = 0; at < records.size(); at += per_chunk) {
      std::vector<std::uint8_t> chunk;
      const auto end = std::min(records.size(), at + per_chunk);
      for (std::size_t i = at; i < end; ++i)
        append_tick_record(records[i], chunk);
      recordings_.append_chunk(recording_, seq_++,
                               static_cast<std::int64_t>(records[at].tick * kTickS * 1e6), chunk,
                               static_cast<double>(records[end - 1].tick + 1) * kTickS);
    }
  }

  // A new session of tess with its recording holding #records in one chunk; scores it on #task
  // with what the simulation measured (#simulated).
  std::vector<curriculum::MetricResult> score_new_session(
      const std::vector<TickRecord>& records, const curriculum::Task& task,
      std::span<const curriculum::MetricValue> simulated = {}) {
    const auto session = db::TrainingRepo(db_).create_session(trainee_, std::nullopt, "t", kNow);
    const auto recording = recordings_.create(session, "scenes/palpation.json", "0123456789abcdef",
                                              0, 1 / kTickS, kNow);
    std::vector<std::uint8_t> chunk;
    for (const auto& r : records)
      append_tick_record(r, chunk);
    recordings_.append_chunk(recording, 0, 0, chunk, static_cast<double>(records.size()) * kTickS);
    return score_session(db_, session, recording, task, kTickS, kNow + 60, simulated);
  }

  incise::test::TempDir dir_;
  db::Database db_{dir_.path() / "incise.db"};
  db::RecordingsRepo recordings_{db_};
  std::int64_t trainee_ = 0;
  std::int64_t session_ = 0;
  std::int64_t recording_ = 0;
  std::int64_t seq_ = 0;
};

// The value of `key` among the metrics, which must hold it.
double value_of(const std::vector<curriculum::MetricValue>& values, const std::string& key) {
  const auto it = std::find_if(values.begin(), values.end(),
                               [&](const curriculum::MetricValue& v) { return v.key == key; });
  if (it == values.end()) throw std::logic_error("no metric " + key);
  return it->value;
}

TEST_F(ScoreSession, StoresTheCurriculumsMetricsOfTheRecordingWithTheirPassFlags) {
  const auto records = wandering_records(0, 1234, 2);
  record(records, 250);  // 5 chunks, the last one short
  const auto expected = curriculum::basic_metrics(tool_samples(records, kTickS));
  const double time = value_of(expected, "completion_time_s");
  const double path = value_of(expected, "path_length_m");
  const double peak = value_of(expected, "peak_force_n");
  const double rms = value_of(expected, "rms_force_n");
  EXPECT_DOUBLE_EQ(time, 1233 * kTickS);
  ASSERT_GT(path, 0);
  ASSERT_GT(peak, 0);

  // Thresholds either side of the measured values, and one exactly on it (the boundary passes).
  curriculum::Task task;
  task.key = "palpation";
  task.scene = "scenes/palpation.json";
  using curriculum::ThresholdOp;
  task.metrics = {
      {"completion_time_s", {ThresholdOp::at_most, time + 1}, "s"},  // passes
      {"path_length_m", {ThresholdOp::at_most, path / 2}, "m"},      // fails
      {"peak_force_n", {ThresholdOp::at_least, peak}, "N"},          // passes on the boundary
      {"rms_force_n", {ThresholdOp::at_least, rms * 1.01}, "N"},     // fails
  };
  const auto results = score_session(db_, session_, recording_, task, kTickS, kNow + 60);
  ASSERT_EQ(results.size(), 4u);
  const bool expected_pass[] = {true, false, true, false};
  for (std::size_t i = 0; i < results.size(); ++i) {
    EXPECT_EQ(results[i].key, task.metrics[i].key);
    EXPECT_EQ(results[i].value, value_of(expected, task.metrics[i].key));
    EXPECT_EQ(results[i].passed, expected_pass[i]) << results[i].key;
    EXPECT_EQ(results[i].threshold, task.metrics[i].threshold);
  }

  auto stored = db::TrainingRepo(db_).scores();
  ASSERT_EQ(stored.size(), 4u);
  std::sort(stored.begin(), stored.end(),
            [](const db::ScoreRecord& a, const db::ScoreRecord& b) { return a.id < b.id; });
  for (std::size_t i = 0; i < stored.size(); ++i) {
    const auto& s = stored[i];
    EXPECT_EQ(s.session_id, session_);
    EXPECT_EQ(s.trainee, "tess");
    EXPECT_EQ(s.metric, task.metrics[i].key);
    EXPECT_EQ(s.value, value_of(expected, s.metric));  // REAL columns keep doubles exactly
    EXPECT_EQ(s.unit, task.metrics[i].unit);
    EXPECT_EQ(s.passed, expected_pass[i]) << s.metric;
    EXPECT_EQ(s.created_at, kNow + 60);
    // With the threshold it was judged against.
    EXPECT_EQ(s.threshold_op, curriculum::threshold_op_symbol(task.metrics[i].threshold.op));
    EXPECT_EQ(s.threshold_value, task.metrics[i].threshold.value);
  }
}

// A two-handed recording scores both hands: the right hand moves straight along x at 5 cm/s
// for 2 s; the left hand either mirrors it or holds still.
TEST_F(ScoreSession, TwoHandedRecordingsScoreEachHandAndTheirCoordination) {
  for (const bool left_moves : {true, false}) {
    SCOPED_TRACE(left_moves ? "left hand moves" : "left hand still");
    std::vector<TickRecord> records(1000);
    for (std::uint32_t i = 0; i < records.size(); ++i) {
      TickRecord& r = records[i];
      r.tick = i;
      const double x = 0.01 + 0.05 * i * kTickS;
      r.input.position = {x, 0.04, 0.04};
      r.has_second = true;
      r.second.input.device_index = 1;
      r.second.input.position = {left_moves ? x : 0.01, 0.02, 0.04};
    }
    const auto values = session_metrics(records, kTickS, curriculum::Task{});
    // The right hand: a straight line, 0.05 m/s for 999 ticks.
    EXPECT_NEAR(value_of(values, "path_length_m"), 0.05 * 999 * kTickS, 1e-12);
    EXPECT_NEAR(value_of(values, "economy_of_motion"), 1.0, 1e-12);
    EXPECT_EQ(value_of(values, "movements"), 1.0);
    // The left hand's metrics carry the suffix; the coordination compares them.
    EXPECT_NEAR(value_of(values, "path_length_m_left"), left_moves ? 0.05 * 999 * kTickS : 0.0,
                1e-12);
    EXPECT_NEAR(value_of(values, "path_length_ratio"), left_moves ? 1.0 : 0.0, 1e-12);
    EXPECT_NEAR(value_of(values, "bimanual_dexterity"), left_moves ? 1.0 : 0.0, 1e-12);

    // A task that asks for both hands moving together passes only when they do.
    curriculum::Task task;
    task.metrics = {{"bimanual_dexterity", {curriculum::ThresholdOp::at_least, 0.5}, ""}};
    const auto results = score_new_session(records, task);
    ASSERT_EQ(results.size(), 1u);
    EXPECT_EQ(results[0].passed, left_moves);
  }
}

// A never event fails the attempt outright: the tip passes through a never zone on its way, every
// metric the task names passes, and the attempt fails on never_events alone. The same run beside
// the zone passes.
TEST_F(ScoreSession, ANeverEventFailsAnAttemptWhoseMetricsAllPass) {
  curriculum::Task task;
  task.metrics = {{"path_length_m", {curriculum::ThresholdOp::at_most, 1.0}, "m"}};
  task.protected_zones = {{{"vessel", {0.05, 0.0, 0.04}, 0.005}, true}};
  for (const double y : {0.0, 0.02}) {
    SCOPED_TRACE(y == 0.0 ? "through the zone" : "beside the zone");
    std::vector<TickRecord> records(1000);
    for (std::uint32_t i = 0; i < records.size(); ++i) {
      records[i].tick = i;
      records[i].input.position = {0.1 * i * kTickS, y, 0.04};  // 0 to 0.2 m along x
    }
    const auto results = score_new_session(records, task);
    ASSERT_EQ(results.size(), 2u);
    EXPECT_TRUE(results[0].passed);
    EXPECT_EQ(results[1].key, "never_events");
    EXPECT_EQ(results[1].value, y == 0.0 ? 1.0 : 0.0);
    EXPECT_EQ(curriculum::attempt_passed(results), y != 0.0);

    // The review shows the event where the tip crossed into the zone (x = 0.045 m at 0.1 m/s:
    // 0.45 s).
    const auto review = review_session(records, kTickS, task, 0.1);
    const auto never = std::count_if(review.events.begin(), review.events.end(), [](const auto& e) {
      return e.kind == curriculum::EventKind::never_event;
    });
    EXPECT_EQ(never, y == 0.0 ? 1 : 0);
    if (y == 0.0) {
      const auto& e = *std::find_if(review.events.begin(), review.events.end(), [](const auto& e) {
        return e.kind == curriculum::EventKind::never_event;
      });
      // The first tick strictly inside: x > 0.045 m, i.e. the tick at 0.45 s or the next.
      EXPECT_GE(e.t_s, 0.45 - 1e-9);
      EXPECT_LE(e.t_s, 0.45 + kTickS + 1e-9);
    }
    EXPECT_EQ(review.timeline.t_s.size(), 20u);  // 1.998 s in bins of 0.1 s
  }
}

// A surgical scene's cut: scored from what the simulation measured, and a protected tissue cut
// counts as a never event with those the recording shows, failing the attempt.
TEST_F(ScoreSession, TheSimulationsCutIsScoredAndAProtectedCutIsANeverEvent) {
  curriculum::Task task;
  task.metrics = {{"cut_area_m2", {curriculum::ThresholdOp::at_least, 60e-6}, "m^2"},
                  {"cut_on_target_fraction", {curriculum::ThresholdOp::at_least, 0.8}, ""},
                  {"never_events", {curriculum::ThresholdOp::at_most, 0}, "count"}};
  std::vector<TickRecord> records(100);
  for (std::uint32_t i = 0; i < records.size(); ++i)
    records[i].tick = i;
  sim::tools::DamageMetrics cut;
  cut.cut_area = 100e-6;
  cut.cut_area_outside_target = 10e-6;
  for (const bool protected_cut : {false, true}) {
    SCOPED_TRACE(protected_cut ? "into the protected tissue" : "clear of it");
    cut.never_event = protected_cut;
    const auto results = score_new_session(records, task, simulation_metrics(cut));
    ASSERT_EQ(results.size(), 3u);
    EXPECT_EQ(results[0].value, 100e-6);
    EXPECT_TRUE(results[0].passed);
    EXPECT_DOUBLE_EQ(results[1].value, 0.9);
    EXPECT_TRUE(results[1].passed);
    EXPECT_EQ(results[2].value, protected_cut ? 1.0 : 0.0);
    EXPECT_EQ(curriculum::attempt_passed(results), !protected_cut);
  }
  // Without a cut nothing is on target.
  EXPECT_EQ(value_of(simulation_metrics({}), "cut_on_target_fraction"), 0.0);
}

TEST_F(ScoreSession, LoadsEveryChunkInOrder) {
  const auto records = wandering_records(0, 600, 3);
  record(records, 7);
  const auto loaded = load_tick_records(db_, recording_);
  ASSERT_EQ(loaded.size(), records.size());
  for (std::size_t i = 0; i < records.size(); ++i) {
    EXPECT_EQ(loaded[i].tick, records[i].tick);
    EXPECT_EQ(loaded[i].input, records[i].input);
  }
  EXPECT_TRUE(load_tick_records(db_, recording_ + 1).empty());  // unknown: no chunks
}

TEST_F(ScoreSession, MalformedChunkIsNamedAndNothingIsStored) {
  record(wandering_records(0, 20, 4), 20);
  std::vector<std::uint8_t> truncated;
  append_tick_record(wandering_records(20, 1, 5)[0], truncated);
  truncated.pop_back();
  recordings_.append_chunk(recording_, seq_++, 40'000, truncated, 0.042);

  curriculum::Task task;
  task.metrics = {{"path_length_m", {curriculum::ThresholdOp::at_most, 1}, "m"}};
  try {
    score_session(db_, session_, recording_, task, kTickS, kNow);
    FAIL() << "a malformed chunk was scored";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "recording " + std::to_string(recording_) +
                  " chunk 1: chunk of 76 bytes is not a whole number of 77-byte tick records");
  }
  EXPECT_TRUE(db::TrainingRepo(db_).scores().empty());
}

TEST_F(ScoreSession, GapBetweenChunksIsNamed) {
  record(wandering_records(0, 10, 6), 10);
  record(wandering_records(11, 10, 7), 10);
  try {
    load_tick_records(db_, recording_);
    FAIL() << "a gap in the ticks was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "recording " + std::to_string(recording_) + " chunk 1: tick 11 follows tick 9");
  }
}

}  // namespace
}  // namespace incise::server::live
