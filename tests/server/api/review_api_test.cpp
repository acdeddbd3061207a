// The review of an attempt (GET /api/sessions/{id}/review) and the expert benchmarks
// (PUT /api/sessions/{id}/expert, GET /api/benchmarks), through the router on a real SQLite file
// with a real recording.

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "api_test_app.h"
#include "curriculum/benchmarks.h"
#include "db/auth_sessions_repo.h"
#include "db/recordings_repo.h"
#include "db/session_events_repo.h"
#include "db/training_repo.h"
#include "server/live/tick_record.h"

namespace incise::server::test {
namespace {

constexpr double kTickHz = 500;

class ReviewApi : public ApiTest {
 protected:
  // A finished palpation attempt of tess: `seconds` of the probe pressing down with a force
  // rising linearly from 0 to peak_n, scored with one peak_force_n value; #who's when given.
  std::int64_t attempt(double seconds, double peak_n, double score, std::int64_t who = 0) {
    db::TrainingRepo training(db());
    const auto session =
        training.create_session(who != 0 ? who : tess_, std::nullopt, "palpation", now());
    db::RecordingsRepo recordings(db());
    const auto recording =
        recordings.create(session, "scenes/palpation.json", "v", 0, kTickHz, now());
    std::vector<std::uint8_t> chunk;
    const auto ticks = static_cast<std::uint32_t>(seconds * kTickHz);
    for (std::uint32_t i = 0; i < ticks; ++i) {
      live::TickRecord r;
      r.tick = i;
      r.input.position = {0.04, 0.04, 0.03};
      r.force[2] = static_cast<float>(peak_n * i / (ticks - 1));
      live::append_tick_record(r, chunk);
    }
    recordings.append_chunk(recording, 0, 0, chunk, seconds);
    recordings.finish(recording, seconds);
    training.set_session_state(session, "finished", now() + 60);
    training.add_score(session, "peak_force_n", score, "N", score <= 4, now() + 60);
    return session;
  }

  void SetUp() override {
    ApiTest::SetUp();
    // The benchmarks here are the test's own: the demo's expert runs are unmarked (they are
    // checked in DemoExpertRunsGiveEveryTaskItsBand).
    db().exec("DELETE FROM expert_runs");
    tess_ = add_trainee("tess");
    tess_token_ = db::AuthSessionsRepo(db()).create(tess_, now(), 3600);
  }

  std::int64_t tess_ = 0;
  std::string tess_token_;
};

TEST_F(ReviewApi, TheReviewShowsEventsTimelinesAndResultsAgainstThresholds) {
  const auto session = attempt(2.0, 2.0, 3.0);
  // Stored after peak_force_n, listed after it: results come in the order the task scores them.
  db::TrainingRepo(db()).add_score(session, "never_events", 0, "count", true, now() + 60);
  const auto review =
      json_of(get("/api/sessions/" + std::to_string(session) + "/review", tess_token_));
  ASSERT_TRUE(review.is_object()) << review;
  EXPECT_EQ(review["task"], "palpation");
  EXPECT_EQ(review["expert_run"], false);
  // The force passes 0.05 N (contact) at tick ceil(0.05 / 2 * 999) = 25, i.e. 0.05 s.
  // The tip rests on the demo task's "centre" target: reached in the first sample.
  const auto& events = review["events"];
  ASSERT_EQ(events.size(), 2u) << events;
  EXPECT_EQ(events[0]["kind"], "target");
  EXPECT_EQ(events[0]["t_s"], 0.0);
  EXPECT_EQ(events[0]["label"], "reached target \"centre\"");
  const auto& contact = events[1];
  EXPECT_EQ(contact["kind"], "contact");
  EXPECT_EQ(contact["hand"], 0);
  EXPECT_NEAR(contact["t_s"].get<double>(), 25 / kTickHz, 1e-9);
  // 2 s in bins of 50 ms; the force is a ramp, so each bin's peak is its last sample's.
  const auto& timeline = review["timeline"];
  ASSERT_EQ(timeline["t_s"].size(), 40u);
  ASSERT_EQ(timeline["hands"].size(), 1u);
  const auto& force = timeline["hands"][0]["peak_force_n"];
  EXPECT_NEAR(force[39].get<double>(), 2.0, 1e-6);
  EXPECT_NEAR(force[0].get<double>(), 2.0 * 24 / 999, 1e-6);
  // Below the task's safe force (3 N), the tissue is never overloaded.
  EXPECT_EQ(timeline["damage_ns"][39].get<double>(), 0.0);
  // The stored scores, with the thresholds the demo task sets: the artery is a never zone, so
  // never_events is scored too.
  ASSERT_EQ(review["results"].size(), 2u);
  const auto& result = review["results"][0];
  EXPECT_EQ(result["metric"], "peak_force_n");
  EXPECT_EQ(result["threshold"]["op"], "<=");
  EXPECT_EQ(result["threshold"]["value"], 4.0);
  EXPECT_TRUE(result["expert"].is_null());
  // No signal stored for this attempt: no simulation damage timeline.
  EXPECT_TRUE(review["sim_damage"].is_null());
  const auto& never = review["results"][1];
  EXPECT_EQ(never["metric"], "never_events");
  EXPECT_EQ(never["threshold"], (nlohmann::json{{"op", "<="}, {"value", 0.0}}));
}

TEST_F(ReviewApi, AdminsMarkExpertRunsWhoseScoresMakeTheBenchmark) {
  const auto admin = session_of(Who::admin);
  const std::vector<double> expert_values = {1.5, 2.0, 2.9};
  std::vector<std::int64_t> experts;
  const auto ines = user_id("instructor");  // experts are the staff
  for (const double v : expert_values)
    experts.push_back(attempt(0.5, 1.0, v, ines));
  for (const auto s : experts) {
    const auto marked =
        put("/api/sessions/" + std::to_string(s) + "/expert", {{"expert", true}}, admin);
    ASSERT_EQ(marked.result_int(), 200) << marked.body();
  }
  // Marking twice changes nothing; a running attempt cannot be an expert run.
  EXPECT_EQ(
      put("/api/sessions/" + std::to_string(experts[0]) + "/expert", {{"expert", true}}, admin)
          .result_int(),
      200);
  db::TrainingRepo training(db());
  const auto running = training.create_session(ines, std::nullopt, "palpation", now());
  EXPECT_TRUE(is_error(
      put("/api/sessions/" + std::to_string(running) + "/expert", {{"expert", true}}, admin),
      http::status::conflict));
  // A trainee's attempt never makes the benchmark: it would publish their scores.
  EXPECT_TRUE(is_error(put("/api/sessions/" + std::to_string(attempt(0.5, 1.0, 2.0)) + "/expert",
                           {{"expert", true}}, admin),
                       http::status::unprocessable_entity));
  EXPECT_TRUE(is_error(
      put("/api/sessions/" + std::to_string(experts[0]) + "/expert", {{"expert", "yes"}}, admin),
      http::status::unprocessable_entity));
  EXPECT_EQ(count("audit_log WHERE action = 'benchmark.add'"), 3);  // marking twice: once

  const auto stats = curriculum::summarize(expert_values);
  const auto benchmarks = json_of(get("/api/benchmarks", tess_token_));
  ASSERT_EQ(benchmarks.size(), 1u) << benchmarks;
  EXPECT_EQ(benchmarks[0]["task"], "palpation");
  EXPECT_EQ(benchmarks[0]["metric"], "peak_force_n");
  EXPECT_EQ(benchmarks[0]["n"], 3);
  EXPECT_NEAR(benchmarks[0]["mean"].get<double>(), (1.5 + 2.0 + 2.9) / 3, 1e-12);
  EXPECT_NEAR(benchmarks[0]["sd"].get<double>(), stats.sd, 1e-12);

  // A trainee's attempt is scored relative to the experts: (value - mean) / sd.
  const auto mine = attempt(0.5, 1.0, 3.6);
  const auto review =
      json_of(get("/api/sessions/" + std::to_string(mine) + "/review", tess_token_));
  const auto& expert = review["results"][0]["expert"];
  EXPECT_EQ(expert["n"], 3);
  EXPECT_NEAR(expert["z"].get<double>(), (3.6 - stats.mean) / stats.sd, 1e-12);

  // Unmarking takes a run out of the benchmark.
  ASSERT_EQ(
      put("/api/sessions/" + std::to_string(experts[2]) + "/expert", {{"expert", false}}, admin)
          .result_int(),
      200);
  EXPECT_EQ(json_of(get("/api/benchmarks", tess_token_))[0]["n"], 2);
}

// The demo's expert runs (server/demo_data.cpp): three per task, every scored metric with its
// band, so a trainee's chart and result show the experts from the first day.
TEST_F(ApiTest, DemoExpertRunsGiveEveryTaskItsBand) {
  const auto benchmarks = json_of(get("/api/benchmarks", session_of(Who::trainee)));
  ASSERT_TRUE(benchmarks.is_array()) << benchmarks;
  const auto band = [&](const std::string& task, const std::string& metric) {
    for (const auto& b : benchmarks)
      if (b["task"] == task && b["metric"] == metric) return b;
    return nlohmann::json();
  };
  for (const auto& [task, metric] :
       {std::pair{"palpation", "peak_force_n"}, std::pair{"palpation", "tissue_contact_s"},
        std::pair{"bimanual_palpation", "completion_time_s"}, std::pair{"liver_cut", "cut_area_m2"},
        std::pair{"knee_tour", "targets_fraction"},
        std::pair{"knee_meniscectomy", "never_events"}}) {
    const auto b = band(task, metric);
    ASSERT_FALSE(b.is_null()) << task << " " << metric;
    EXPECT_EQ(b["n"], 3) << task << " " << metric;
  }
  // Better than the threshold, and spread: a band, not a line.
  EXPECT_LT(band("palpation", "peak_force_n")["mean"].get<double>(), 4.0);
  EXPECT_GT(band("palpation", "peak_force_n")["sd"].get<double>(), 0.0);
  EXPECT_GT(band("liver_cut", "cut_area_m2")["mean"].get<double>(), 6e-5);
}

TEST_F(ReviewApi, AnAttemptWithoutACompleteRecordingHasNoReview) {
  db::TrainingRepo training(db());
  const auto session = training.create_session(tess_, std::nullopt, "palpation", now());
  const auto path = "/api/sessions/" + std::to_string(session) + "/review";
  EXPECT_TRUE(is_error(get(path, tess_token_), http::status::conflict,
                       "session " + std::to_string(session) + " has no recording"));
  db::RecordingsRepo(db()).create(session, "scenes/palpation.json", "v", 0, kTickHz, now());
  EXPECT_TRUE(is_error(get(path, tess_token_), http::status::conflict,
                       "session " + std::to_string(session) + " is still being recorded"));
  EXPECT_TRUE(is_error(get("/api/sessions/999999/review", tess_token_), http::status::not_found));
}

// The simulation's damage index sampled during the live run comes with the review as stored.
TEST_F(ReviewApi, TheReviewCarriesTheSimulationsDamageTimeline) {
  const auto session = attempt(1.0, 1.0, 1.0);
  db::TrainingRepo(db()).set_signal(session, "damage_index", {0.1, {0, 0, 0.01, 0.02}});
  const auto review =
      json_of(get("/api/sessions/" + std::to_string(session) + "/review", tess_token_));
  EXPECT_EQ(review["sim_damage"],
            (nlohmann::json{{"interval_s", 0.1}, {"values", {0.0, 0.0, 0.01, 0.02}}}));
}

// The events the simulation saw (stored with the session) come among the recording's, in time
// order, each saying where it came from.
TEST_F(ReviewApi, TheSimulationsEventsComeInTimeOrderAmongTheRecordings) {
  const auto session = attempt(2.0, 2.0, 3.0);
  db::SessionEventsRepo(db()).set(
      session, std::vector<db::SessionEvent>{{0.02, "grasp", 1, "3 vertices"},
                                             {1.5, "cut", 0, "cut 12.0 mm^2"},
                                             {1.5, "never_event", 0, "a protected tissue"}});
  const auto review =
      json_of(get("/api/sessions/" + std::to_string(session) + "/review", tess_token_));
  const auto& events = review["events"];
  ASSERT_EQ(events.size(), 5u) << events;
  // The recording's target (0 s) and contact (0.05 s) around the simulation's grasp (0.02 s).
  EXPECT_EQ(events[0]["kind"], "target");
  EXPECT_EQ(events[0]["source"], "recording");
  EXPECT_EQ(events[1], (nlohmann::json{{"t_s", 0.02},
                                       {"kind", "grasp"},
                                       {"hand", 1},
                                       {"label", "3 vertices"},
                                       {"source", "simulation"}}));
  EXPECT_EQ(events[2]["kind"], "contact");
  EXPECT_EQ(events[3]["kind"], "cut");
  EXPECT_EQ(events[4]["kind"], "never_event");
  EXPECT_EQ(events[4]["source"], "simulation");
}

// A score shows the threshold it was judged against; when the curriculum changed it since, the
// task's threshold today comes beside it. A score stored without one (before migration 008)
// shows today's.
TEST_F(ReviewApi, ResultsShowTheThresholdTheAttemptWasJudgedAgainst) {
  const auto session = attempt(1.0, 1.0, 3.0);  // peak_force_n stored without a threshold
  db::TrainingRepo training(db());
  training.add_scores(session, {{{"contact_time_s", 6.0, "s", true, ">=", 4.0}}}, now() + 60);
  const auto results =
      json_of(get("/api/sessions/" + std::to_string(session) + "/review", tess_token_))["results"];
  std::map<std::string, nlohmann::json> by_metric;
  for (const auto& r : results)
    by_metric[r["metric"].get<std::string>()] = r;
  // The demo task asks contact_time_s >= 5 today; the attempt was judged against >= 4.
  EXPECT_EQ(by_metric["contact_time_s"]["threshold"],
            (nlohmann::json{{"op", ">="}, {"value", 4.0}}));
  EXPECT_EQ(by_metric["contact_time_s"]["threshold_now"],
            (nlohmann::json{{"op", ">="}, {"value", 5.0}}));
  EXPECT_EQ(by_metric["peak_force_n"]["threshold"], (nlohmann::json{{"op", "<="}, {"value", 4.0}}));
  EXPECT_TRUE(by_metric["peak_force_n"]["threshold_now"].is_null());
}

}  // namespace
}  // namespace incise::server::test
