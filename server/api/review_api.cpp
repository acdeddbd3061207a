// The review page of an attempt: its events and signal timelines computed
// from the recording, its results against the task's thresholds and the experts, and the expert
// runs that make the benchmarks.

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "curriculum/benchmarks.h"
#include "curriculum/metrics.h"
#include "db/recordings_repo.h"
#include "db/reviews_repo.h"
#include "db/session_events_repo.h"
#include "db/training_repo.h"
#include "db/transaction.h"
#include "db/users_repo.h"
#include "server/api/api_error.h"
#include "server/api/audit_change.h"
#include "server/api/handlers.h"
#include "server/api/live_access.h"
#include "server/api/request_fields.h"
#include "server/live/scoring.h"

namespace incise::server::api {
namespace {

// One bin per 50 ms: a two-minute attempt plots 2,400 points per signal, fine enough to see a
// force spike's time to a frame and small enough to send at once.
constexpr double kTimelineInterval = 0.05;

// The experts' benchmarks from the stored expert runs (the grouping is curriculum/benchmarks.h's).
std::map<std::pair<std::string, std::string>, curriculum::Benchmark> benchmarks(db::Database& db) {
  std::vector<curriculum::ExpertScore> scores;
  for (const auto& s : db::ReviewsRepo(db).expert_scores())
    scores.push_back({s.task, s.metric, s.value, s.unit});
  return curriculum::group_benchmarks(scores);
}

nlohmann::json to_json(const curriculum::BenchmarkStats& b) {
  return {{"n", b.n},           {"mean", b.mean}, {"sd", b.sd},
          {"median", b.median}, {"p10", b.p10},   {"p90", b.p90}};
}

// A number, or null where it is undefined (JSON has no NaN).
nlohmann::json finite_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

nlohmann::json timeline_json(const curriculum::Timeline& t) {
  auto hands = nlohmann::json::array();
  for (int h = 0; h < 2; ++h) {
    if (t.peak_force_n[h].empty() && h > 0) break;
    hands.push_back({{"peak_force_n", t.peak_force_n[h]}, {"speed_m_s", t.speed_m_s[h]}});
  }
  return {
      {"interval_s", t.interval_s}, {"t_s", t.t_s}, {"hands", hands}, {"damage_ns", t.damage_ns}};
}

// The simulation's damage index sampled during the live run (session_signals), or null for a
// session run before it was measured.
nlohmann::json sim_damage_json(db::Database& db, std::int64_t session_id) {
  const auto signal = db::TrainingRepo(db).signal(session_id, "damage_index");
  if (!signal) return nullptr;
  return {{"interval_s", signal->interval_s}, {"values", signal->values}};
}

// The session's stored scores in the order the task scores them (others after), with the
// thresholds they were judged against and the experts' benchmark.
nlohmann::json results_json(db::Database& db, const db::SessionRecord& session,
                            const curriculum::Task* task) {
  const auto experts = benchmarks(db);
  const auto requirements =
      task ? curriculum::scored_requirements(*task) : std::vector<curriculum::MetricRequirement>{};
  auto scores = db::TrainingRepo(db).session_scores(session.id);
  const auto rank = [&](const std::string& metric) {
    const auto it = std::find_if(requirements.begin(), requirements.end(),
                                 [&](const auto& r) { return r.key == metric; });
    return it - requirements.begin();
  };
  std::stable_sort(scores.begin(), scores.end(),
                   [&](const auto& a, const auto& b) { return rank(a.metric) < rank(b.metric); });

  auto out = nlohmann::json::array();
  for (const auto& score : scores) {
    nlohmann::json row = {{"metric", score.metric}, {"value", score.value},
                          {"unit", score.unit},     {"passed", score.passed},
                          {"threshold", nullptr},   {"threshold_now", nullptr},
                          {"expert", nullptr},      {"criterion", score.criterion}};
    // The threshold the score was judged against; the task's today when it differs (the
    // curriculum changed since), or when the score predates stored thresholds.
    const auto r = static_cast<std::size_t>(rank(score.metric));
    nlohmann::json now = nullptr;
    if (r < requirements.size()) {
      const auto& threshold = requirements[r].threshold;
      now = {{"op", curriculum::threshold_op_symbol(threshold.op)}, {"value", threshold.value}};
    }
    if (!score.threshold_op.empty()) {
      row["threshold"] = {{"op", score.threshold_op}, {"value", score.threshold_value}};
      if (!now.is_null() && now != row["threshold"]) row["threshold_now"] = now;
    } else {
      row["threshold"] = now;
    }
    const auto expert = experts.find({session.task, score.metric});
    if (expert != experts.end()) {
      row["expert"] = to_json(expert->second.stats);
      row["expert"]["z"] =
          finite_or_null(curriculum::relative_score(score.value, expert->second.stats));
    }
    out.push_back(std::move(row));
  }
  return out;
}

}  // namespace

ApiResponse session_review(ApiContext& ctx) {
  auto& db = ctx.db();
  const auto session = visible_session(ctx);
  const auto name = "session " + std::to_string(session.id);
  const auto recording = db::RecordingsRepo(db).find_by_session(session.id);
  if (!recording) throw ApiError(http::status::conflict, name + " has no recording");
  if (recording->state != "complete") {
    throw ApiError(http::status::conflict, name + " is still being recorded");
  }
  // A task since removed from every curriculum still has its motion and force events; only its
  // zones and thresholds are gone.
  const auto task = find_curriculum_task(db, session.task);
  curriculum::Task events_task = task.value_or(curriculum::Task{});
  const auto ticks = live::load_tick_records(db, recording->id);
  const auto tick_s = recording->tick_hz > 0 ? 1.0 / recording->tick_hz : 0.002;
  const auto review = live::review_session(ticks, tick_s, events_task, kTimelineInterval);

  // The recording's events and those the simulation saw (a surgical scene's grasps, cuts,
  // collisions and never events), in time order; at equal times the recording's first.
  std::vector<nlohmann::json> events;
  for (const auto& e : review.events) {
    events.push_back({{"t_s", e.t_s},
                      {"kind", curriculum::event_kind_name(e.kind)},
                      {"hand", e.hand},
                      {"label", e.label},
                      {"source", "recording"}});
  }
  for (const auto& e : db::SessionEventsRepo(db).list(session.id)) {
    events.push_back({{"t_s", e.t_s},
                      {"kind", e.kind},
                      {"hand", e.hand},
                      {"label", e.label},
                      {"source", "simulation"}});
  }
  std::stable_sort(events.begin(), events.end(), [](const auto& a, const auto& b) {
    return a["t_s"].template get<double>() < b["t_s"].template get<double>();
  });
  return {http::status::ok,
          {{"session_id", session.id},
           {"task", session.task},
           {"trainee_id", session.trainee_id},
           {"recording_id", recording->id},
           {"duration_s", recording->duration_s},
           {"expert_run", db::ReviewsRepo(db).is_expert_run(session.id)},
           {"events", nlohmann::json(std::move(events))},
           {"timeline", timeline_json(review.timeline)},
           {"sim_damage", sim_damage_json(db, session.id)},
           {"results", results_json(db, session, task ? &*task : nullptr)}}};
}

ApiResponse set_expert_run(ApiContext& ctx) {
  const auto& admin = ctx.require_role({db::Role::admin, db::Role::instructor});
  const auto session = visible_session(ctx);
  if (admin.role == db::Role::instructor && session.trainee_id != admin.id) {
    throw ApiError(http::status::forbidden,
                   "an instructor marks only their own attempts as expert runs; ask an admin");
  }
  const auto body = ctx.json_body();
  const RequestFields fields(body, {"expert"});
  const bool expert = fields.boolean("expert");
  auto& db = ctx.db();
  const auto name = "session " + std::to_string(session.id);
  if (expert) {
    // Experts are the staff: a trainee's attempt in the benchmark would publish their scores.
    const auto who = db::UsersRepo(db).find(session.trainee_id);
    if (!who || who->role == db::Role::trainee) {
      throw ApiError(http::status::unprocessable_entity,
                     name + " is a trainee's attempt; expert runs are instructors' or admins'");
    }
    if (session.state != "finished" || db::TrainingRepo(db).session_scores(session.id).empty()) {
      throw ApiError(http::status::conflict, name + " is not a finished, scored attempt");
    }
  }
  db::ReviewsRepo reviews(db);
  db::Transaction tx(db);  // two marks at once log one change, not two
  if (reviews.is_expert_run(session.id) != expert) {
    reviews.set_expert_run(session.id, expert, admin.id, ctx.now);
    audit_change(db, admin.id, expert ? "benchmark.add" : "benchmark.remove",
                 name + " task " + session.task, ctx.now, {{"expert_run", !expert}},
                 {{"expert_run", expert}});
  }
  tx.commit();
  return {http::status::ok, {{"session_id", session.id}, {"expert_run", expert}}};
}

ApiResponse list_benchmarks(ApiContext& ctx) {
  ctx.user();
  auto out = nlohmann::json::array();
  for (const auto& [key, entry] : benchmarks(ctx.db())) {
    auto row = to_json(entry.stats);
    row["task"] = key.first;
    row["metric"] = key.second;
    row["unit"] = entry.unit;
    out.push_back(std::move(row));
  }
  return {http::status::ok, std::move(out)};
}

}  // namespace incise::server::api
