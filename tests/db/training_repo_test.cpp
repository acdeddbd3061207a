// Tests for db/training_repo.h: sessions with their state timestamps, recordings and scores, each
// listed newest first for everyone or for one trainee.
#include "db/training_repo.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "db/recordings_repo.h"
#include "db/statement.h"
#include "temp_database.h"

namespace incise::db {
namespace {

using test::row_count;

class TrainingRepoTest : public test::DbTest {
 protected:
  std::int64_t ann_ = test::add_user(db(), "ann");
  std::int64_t bob_ = test::add_user(db(), "bob");
  std::int64_t station_ = test::add_station(db(), "s1");
  TrainingRepo training_{db()};
};

TEST_F(TrainingRepoTest, CreateSessionThenList) {
  const auto with_station = training_.create_session(ann_, station_, "suture", 100);
  const auto without = training_.create_session(bob_, std::nullopt, "incision", 200);
  const auto all = training_.sessions();
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].id, without) << "newest first";
  EXPECT_EQ(all[0].trainee_id, bob_);
  EXPECT_EQ(all[0].trainee, "bob");
  EXPECT_EQ(all[0].station_id, std::nullopt);
  EXPECT_EQ(all[0].station, "");
  EXPECT_EQ(all[0].task, "incision");
  EXPECT_EQ(all[0].state, "created");
  EXPECT_EQ(all[0].started_at, std::nullopt);
  EXPECT_EQ(all[0].ended_at, std::nullopt);
  EXPECT_EQ(all[1].id, with_station);
  EXPECT_EQ(all[1].station_id, station_);
  EXPECT_EQ(all[1].station, "s1");
  EXPECT_EQ(all[1].trainee, "ann");
}

TEST_F(TrainingRepoTest, SessionsFilteredByTrainee) {
  const auto a1 = training_.create_session(ann_, std::nullopt, "t", 1);
  training_.create_session(bob_, std::nullopt, "t", 2);
  const auto a2 = training_.create_session(ann_, std::nullopt, "t", 3);
  const auto anns = training_.sessions(ann_);
  ASSERT_EQ(anns.size(), 2u);
  EXPECT_EQ(anns[0].id, a2);
  EXPECT_EQ(anns[1].id, a1);
  EXPECT_EQ(training_.sessions(bob_).size(), 1u);
  EXPECT_TRUE(training_.sessions(bob_ + 100).empty());
}

TEST_F(TrainingRepoTest, StateChangesStampStartAndEnd) {
  const auto id = training_.create_session(ann_, station_, "suture", 100);
  training_.set_session_state(id, "running", 110);
  auto s = training_.sessions().at(0);
  EXPECT_EQ(s.state, "running");
  EXPECT_EQ(s.started_at, 110);
  EXPECT_EQ(s.ended_at, std::nullopt);

  training_.set_session_state(id, "paused", 120);
  training_.set_session_state(id, "running", 130);
  s = training_.sessions().at(0);
  EXPECT_EQ(s.state, "running");
  EXPECT_EQ(s.started_at, 110) << "started_at is the first start, not the latest";
  EXPECT_EQ(s.ended_at, std::nullopt);

  training_.set_session_state(id, "finished", 140);
  s = training_.sessions().at(0);
  EXPECT_EQ(s.state, "finished");
  EXPECT_EQ(s.started_at, 110);
  EXPECT_EQ(s.ended_at, 140);

  // Ended is final: a late pause (answered after the session thread wrote "finished") changes
  // nothing, and says so.
  EXPECT_FALSE(training_.set_session_state(id, "paused", 150));
  EXPECT_FALSE(training_.set_session_state(id, "aborted", 150));
  s = training_.sessions().at(0);
  EXPECT_EQ(s.state, "finished");
  EXPECT_EQ(s.ended_at, 140);
  EXPECT_THROW(training_.set_session_state(id + 1000, "running", 150), NotFound);
}

TEST_F(TrainingRepoTest, AbortedSessionIsEnded) {
  const auto id = training_.create_session(ann_, std::nullopt, "suture", 100);
  training_.set_session_state(id, "aborted", 105);
  const auto s = training_.sessions().at(0);
  EXPECT_EQ(s.state, "aborted");
  EXPECT_EQ(s.started_at, std::nullopt) << "never ran";
  EXPECT_EQ(s.ended_at, 105);
}

TEST_F(TrainingRepoTest, InvalidStateThrowsConstraintErrorAndChangesNothing) {
  const auto id = training_.create_session(ann_, std::nullopt, "suture", 100);
  training_.set_session_state(id, "running", 110);
  EXPECT_THROW(training_.set_session_state(id, "exploded", 120), ConstraintError);
  EXPECT_THROW(training_.set_session_state(id, "", 120), ConstraintError);
  const auto s = training_.sessions().at(0);
  EXPECT_EQ(s.state, "running");
  EXPECT_EQ(s.started_at, 110);
}

TEST_F(TrainingRepoTest, UnknownSessionIdThrowsNotFound) {
  EXPECT_THROW(training_.set_session_state(4242, "running", 1), NotFound);
}

TEST_F(TrainingRepoTest, SessionOfAnUnknownTraineeIsRefused) {
  EXPECT_THROW(training_.create_session(bob_ + 100, std::nullopt, "t", 1), ConstraintError);
  EXPECT_EQ(row_count(db(), "sessions"), 0);
}

TEST_F(TrainingRepoTest, RecordingsCreateAndListWithFilter) {
  const auto sa = training_.create_session(ann_, std::nullopt, "suture", 1);
  const auto sb = training_.create_session(bob_, std::nullopt, "incision", 2);
  const auto ra = training_.add_recording(sa, 12.5, 10);
  const auto rb = training_.add_recording(sb, 3.25, 20);
  const auto all = training_.recordings();
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].id, rb);
  EXPECT_EQ(all[1].id, ra);
  EXPECT_EQ(all[1].session_id, sa);
  EXPECT_EQ(all[1].trainee, "ann");
  EXPECT_EQ(all[1].task, "suture");
  EXPECT_EQ(all[1].duration_s, 12.5);
  EXPECT_EQ(all[1].created_at, 10);
  const auto anns = training_.recordings(ann_);
  ASSERT_EQ(anns.size(), 1u);
  EXPECT_EQ(anns[0].id, ra);
}

TEST_F(TrainingRepoTest, OneRecordingPerSession) {
  const auto s = training_.create_session(ann_, std::nullopt, "suture", 1);
  training_.add_recording(s, 1.0, 10);
  EXPECT_THROW(training_.add_recording(s, 2.0, 11), ConstraintError);
  EXPECT_THROW(training_.add_recording(s + 100, 2.0, 11), ConstraintError) << "unknown session";
  EXPECT_EQ(row_count(db(), "recordings"), 1);
}

TEST_F(TrainingRepoTest, ScoresCreateAndListWithFilter) {
  const auto sa = training_.create_session(ann_, std::nullopt, "suture", 1);
  const auto sb = training_.create_session(bob_, std::nullopt, "incision", 2);
  const auto depth = training_.add_score(sa, "depth_error", 0.75, "mm", true, 10);
  const auto time = training_.add_score(sa, "time", 95.0, "s", false, 11);
  const auto other = training_.add_score(sb, "depth_error", 2.0, "mm", false, 12);
  const auto all = training_.scores();
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[0].id, other);
  EXPECT_EQ(all[1].id, time);
  EXPECT_EQ(all[2].id, depth);
  EXPECT_EQ(all[2].session_id, sa);
  EXPECT_EQ(all[2].trainee, "ann");
  EXPECT_EQ(all[2].task, "suture");
  EXPECT_EQ(all[2].metric, "depth_error");
  EXPECT_EQ(all[2].value, 0.75);
  EXPECT_EQ(all[2].unit, "mm");
  EXPECT_TRUE(all[2].passed);
  EXPECT_FALSE(all[1].passed);
  EXPECT_EQ(all[2].created_at, 10);
  const auto anns = training_.scores(ann_);
  ASSERT_EQ(anns.size(), 2u);
  for (const auto& s : anns)
    EXPECT_EQ(s.trainee, "ann");
  EXPECT_EQ(training_.scores(bob_).size(), 1u);
}

TEST_F(TrainingRepoTest, OneScorePerSessionAndMetric) {
  const auto sa = training_.create_session(ann_, std::nullopt, "suture", 1);
  const auto sb = training_.create_session(ann_, std::nullopt, "suture", 2);
  training_.add_score(sa, "time", 1.0, "s", true, 10);
  EXPECT_THROW(training_.add_score(sa, "time", 2.0, "s", true, 11), ConstraintError);
  EXPECT_NO_THROW(training_.add_score(sb, "time", 2.0, "s", true, 11)) << "another session";
  EXPECT_NO_THROW(training_.add_score(sa, "depth", 2.0, "mm", true, 11)) << "another metric";
  EXPECT_EQ(row_count(db(), "scores"), 3);
}

TEST_F(TrainingRepoTest, FindSessionMatchesTheListedRecord) {
  const auto id = training_.create_session(ann_, station_, "suture", 100);
  training_.create_session(bob_, std::nullopt, "incision", 200);
  training_.set_session_state(id, "running", 110);
  const auto found = training_.find_session(id);
  ASSERT_TRUE(found.has_value());
  const auto listed = training_.sessions(ann_).at(0);
  EXPECT_EQ(found->id, id);
  EXPECT_EQ(found->trainee_id, listed.trainee_id);
  EXPECT_EQ(found->trainee, "ann");
  EXPECT_EQ(found->station_id, station_);
  EXPECT_EQ(found->station, "s1");
  EXPECT_EQ(found->task, "suture");
  EXPECT_EQ(found->state, "running");
  EXPECT_EQ(found->started_at, 110);
  EXPECT_EQ(found->ended_at, std::nullopt);
  EXPECT_EQ(training_.find_session(4242), std::nullopt);
}

TEST_F(TrainingRepoTest, RecordingsListShowWhetherTheyAreStillRecording) {
  const auto old = training_.create_session(ann_, std::nullopt, "suture", 1);
  const auto live = training_.create_session(ann_, std::nullopt, "suture", 2);
  training_.add_recording(old, 10.0, 10);
  RecordingsRepo(db()).create(live, "scenes/suture.json", "v1", 1, 500.0, 20);
  const auto all = training_.recordings();
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].session_id, live);
  EXPECT_EQ(all[0].state, "recording");
  EXPECT_EQ(all[1].session_id, old);
  EXPECT_EQ(all[1].state, "complete");
}

// Each score of ann's session as metric -> (value, passed, created_at).
std::map<std::string, std::tuple<double, bool, std::int64_t>> scores_by_metric(
    TrainingRepo& training, std::int64_t session) {
  std::map<std::string, std::tuple<double, bool, std::int64_t>> out;
  for (const auto& s : training.scores())
    if (s.session_id == session) out[s.metric] = {s.value, s.passed, s.created_at};
  return out;
}

TEST_F(TrainingRepoTest, AddScoresStoresEveryScore) {
  const auto s = training_.create_session(ann_, std::nullopt, "suture", 1);
  const std::vector<ScoreInput> scores = {{"completion_time_s", 80.5, "s", true},
                                          {"path_length_m", 1.75, "m", false},
                                          {"targets_reached", 1.0, "", true}};
  training_.add_scores(s, scores, 50);
  const auto all = training_.scores();
  ASSERT_EQ(all.size(), 3u);
  for (const auto& input : scores) {
    const auto stored = std::find_if(
        all.begin(), all.end(), [&](const ScoreRecord& r) { return r.metric == input.metric; });
    ASSERT_NE(stored, all.end()) << input.metric;
    EXPECT_EQ(stored->session_id, s);
    EXPECT_EQ(stored->value, input.value);
    EXPECT_EQ(stored->unit, input.unit);
    EXPECT_EQ(stored->passed, input.passed);
    EXPECT_EQ(stored->created_at, 50);
  }
  training_.add_scores(s, {}, 60);
  EXPECT_EQ(row_count(db(), "scores"), 3) << "no scores is a no-op";
}

TEST_F(TrainingRepoTest, AScoreKeepsWhetherItIsACompletionCriterionAndItsThreshold) {
  const auto s = training_.create_session(ann_, std::nullopt, "palpation", 1);
  const std::vector<ScoreInput> scores = {{"tissue_contact_s", 0.0, "s", false, ">=", 2.0, true},
                                          {"peak_force_n", 1.5, "N", true, "<=", 4.0, false}};
  training_.add_scores(s, scores, 50);
  const auto stored = training_.session_scores(s);
  ASSERT_EQ(stored.size(), 2u);
  EXPECT_TRUE(stored[0].criterion);
  EXPECT_EQ(stored[0].threshold_op, ">=");
  EXPECT_EQ(stored[0].threshold_value, 2.0);
  EXPECT_FALSE(stored[1].criterion);
  EXPECT_EQ(stored[1].threshold_value, 4.0);
}

TEST_F(TrainingRepoTest, AddScoresReplacesTheSameMetricsAndKeepsTheOthers) {
  const auto s = training_.create_session(ann_, std::nullopt, "suture", 1);
  const auto other = training_.create_session(ann_, std::nullopt, "suture", 2);
  training_.add_score(s, "completion_time_s", 80.0, "s", true, 10);
  training_.add_score(s, "path_length_m", 1.0, "m", true, 10);
  training_.add_score(other, "completion_time_s", 70.0, "s", true, 10);
  const std::vector<ScoreInput> rescored = {{"completion_time_s", 130.0, "s", false},
                                            {"peak_force_n", 2.0, "N", true}};
  training_.add_scores(s, rescored, 20);
  const auto after = scores_by_metric(training_, s);
  ASSERT_EQ(after.size(), 3u);
  EXPECT_EQ(after.at("completion_time_s"), std::make_tuple(130.0, false, std::int64_t{20}));
  EXPECT_EQ(after.at("path_length_m"), std::make_tuple(1.0, true, std::int64_t{10}));
  EXPECT_EQ(after.at("peak_force_n"), std::make_tuple(2.0, true, std::int64_t{20}));
  EXPECT_EQ(scores_by_metric(training_, other).at("completion_time_s"),
            std::make_tuple(70.0, true, std::int64_t{10}))
      << "another session's score of the same metric";
}

TEST_F(TrainingRepoTest, AddScoresIsAllOrNothing) {
  const auto s = training_.create_session(ann_, std::nullopt, "suture", 1);
  training_.add_score(s, "completion_time_s", 80.0, "s", true, 10);
  // The storage refuses the third score, after the first two were written in the transaction.
  if (db().dialect() == Dialect::sqlite) {
    db().exec(
        "CREATE TRIGGER refuse_boom BEFORE INSERT ON scores WHEN NEW.metric = 'boom' BEGIN "
        "SELECT RAISE(ABORT, 'boom refused'); END");
  } else {
    db().exec(
        "CREATE FUNCTION refuse_boom() RETURNS trigger LANGUAGE plpgsql AS $$ BEGIN RAISE "
        "EXCEPTION 'boom refused' USING ERRCODE = 'check_violation'; END $$; CREATE TRIGGER "
        "refuse_boom BEFORE INSERT ON scores FOR EACH ROW WHEN (NEW.metric = 'boom') EXECUTE "
        "FUNCTION refuse_boom()");
  }
  const std::vector<ScoreInput> scores = {{"completion_time_s", 130.0, "s", false},
                                          {"path_length_m", 1.0, "m", true},
                                          {"boom", 1.0, "", true},
                                          {"peak_force_n", 2.0, "N", true}};
  EXPECT_THROW(training_.add_scores(s, scores, 20), ConstraintError);
  const auto after = scores_by_metric(training_, s);
  ASSERT_EQ(after.size(), 1u) << "a score written before the failure survived";
  EXPECT_EQ(after.at("completion_time_s"), std::make_tuple(80.0, true, std::int64_t{10}))
      << "a replaced score was not restored";

  // The connection is usable afterwards: no transaction was left open.
  db().exec(db().dialect() == Dialect::sqlite ? "DROP TRIGGER refuse_boom"
                                              : "DROP TRIGGER refuse_boom ON scores");
  training_.add_scores(s, scores, 30);
  EXPECT_EQ(scores_by_metric(training_, s).size(), 4u);
}

TEST_F(TrainingRepoTest, AddScoresRefusesBadInputBeforeWriting) {
  const auto s = training_.create_session(ann_, std::nullopt, "suture", 1);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<std::vector<ScoreInput>> bad = {
      {{"a", 1.0, "", true}, {"b", nan, "", true}},
      {{"a", 1.0, "", true}, {"b", -inf, "", true}},
      {{"a", 1.0, "", true}, {"", 1.0, "", true}},
      {{"a", 1.0, "", true}, {"b", 1.0, "", true}, {"a", 2.0, "", false}},
  };
  for (const auto& scores : bad)
    EXPECT_THROW(training_.add_scores(s, scores, 20), std::invalid_argument);
  EXPECT_EQ(row_count(db(), "scores"), 0);
  const std::vector<ScoreInput> good = {{"a", 1.0, "", true}};
  EXPECT_THROW(training_.add_scores(s + 100, good, 20), NotFound);
  EXPECT_EQ(row_count(db(), "scores"), 0);
}

// A session's signals read back bit for bit (awkward values included), are replaced by name,
// are refused with nothing written when they hold a non-finite value, and go with their session.
TEST_F(TrainingRepoTest, SignalsRoundTripExactlyAndGoWithTheirSession) {
  const auto s = training_.create_session(ann_, std::nullopt, "suture", 1);
  const SessionSignal damage{0.1, {0.0, 0.1 + 0.2, 1e-300, 0.5, 1.0}};
  training_.set_signal(s, "damage_index", damage);
  auto read = training_.signal(s, "damage_index");
  ASSERT_TRUE(read.has_value());
  EXPECT_EQ(read->interval_s, 0.1);
  EXPECT_EQ(read->values, damage.values);
  EXPECT_FALSE(training_.signal(s, "other").has_value());
  EXPECT_FALSE(training_.signal(s + 1, "damage_index").has_value());

  training_.set_signal(s, "damage_index", {0.2, {}});
  read = training_.signal(s, "damage_index");
  EXPECT_EQ(read->interval_s, 0.2);
  EXPECT_TRUE(read->values.empty());

  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(training_.set_signal(s, "x", {0.1, {1.0, nan}}), std::invalid_argument);
  EXPECT_THROW(training_.set_signal(s, "x", {0.0, {1.0}}), std::invalid_argument);
  EXPECT_FALSE(training_.signal(s, "x").has_value());

  db().prepare("DELETE FROM sessions WHERE id = ?").bind(1, s).run();
  EXPECT_EQ(row_count(db(), "session_signals"), 0);
}

// A score keeps the threshold it was judged against (migration 008); a score without one reads
// back with none, and an unknown comparison is refused before anything is written.
TEST_F(TrainingRepoTest, ScoresKeepTheThresholdTheyWereJudgedAgainst) {
  const auto s = training_.create_session(ann_, std::nullopt, "suture", 1);
  const std::vector<ScoreInput> scores = {{"peak_force_n", 3.5, "N", true, "<=", 4.0},
                                          {"contact_time_s", 2.0, "s", false, ">=", 5.0},
                                          {"jaw_closures", 3.0, "count", true}};
  training_.add_scores(s, scores, 10);
  const auto read = training_.session_scores(s);
  ASSERT_EQ(read.size(), 3u);
  for (std::size_t i = 0; i < read.size(); ++i) {
    EXPECT_EQ(read[i].metric, scores[i].metric);
    EXPECT_EQ(read[i].threshold_op, scores[i].threshold_op);
    EXPECT_EQ(read[i].threshold_value, scores[i].threshold_value);
  }
  const std::vector<ScoreInput> bad = {{"x", 1.0, "", true, "<", 2.0}};
  EXPECT_THROW(training_.add_scores(s, bad, 11), std::invalid_argument);
  const std::vector<ScoreInput> infinite = {
      {"x", 1.0, "", true, "<=", std::numeric_limits<double>::infinity()}};
  EXPECT_THROW(training_.add_scores(s, infinite, 11), std::invalid_argument);
  EXPECT_EQ(training_.session_scores(s).size(), 3u);
}

}  // namespace
}  // namespace incise::db
