#include "server/demo_data.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "curriculum/curriculum_json.h"
#include "curriculum/metrics.h"
#include "db/curricula_repo.h"
#include "db/reviews_repo.h"
#include "db/stations_repo.h"
#include "db/training_repo.h"
#include "db/transaction.h"
#include "db/users_repo.h"

namespace incise::server {

// Generated from curriculum/demo/basic_skills.json at build time.
extern const char* const kDemoCurriculumJson;

namespace {

// Scores of a passing attempt at #task, every scored requirement (the completion criteria first,
// as scoring stores them) met with a margin: #margin of an "at most" limit (0.6: 60 % of it),
// 1.8 - margin of an "at least" one (1.2 for 0.6); counts whole, shares at most 1, rounded as a
// person would read them.
std::vector<db::ScoreInput> passing_scores(const curriculum::Task& task, double margin) {
  const auto criteria = curriculum::completion_requirements(task).size();
  std::vector<db::ScoreInput> scores;
  for (const auto& metric : curriculum::scored_requirements(task)) {
    const double limit = metric.threshold.value;
    double value = 0;
    if (metric.threshold.op == curriculum::ThresholdOp::at_most) {
      value = limit * margin;
      if (metric.unit == "count") value = std::floor(value);
    } else {
      value = limit * (1.8 - margin);
      if (metric.unit.empty() && limit <= 1) value = std::min(value, 1.0);
    }
    const double step = std::abs(limit) >= 0.01 ? 1e-3 : 1e-9;  // a cut's area is 6e-5 m^2
    value = std::round(value / step) * step;
    scores.push_back({metric.key, value, metric.unit, true,
                      std::string(curriculum::threshold_op_symbol(metric.threshold.op)), limit,
                      scores.size() < criteria});
  }
  return scores;
}

}  // namespace

bool is_demo_station_token(std::string_view token) {
  return token == kDemoStationToken || token == kDemoSurgicalStationToken ||
         token == kDemoArthroscopyStationToken;
}

bool seed_demo_data(db::Database& db, std::int64_t now) {
  db::UsersRepo users(db);
  if (users.count() > 0) return false;
  db::Transaction tx(db);
  const char* display_names[] = {"Ada Admin", "Ines Instructor", "Theo Trainee", "Rita Resident"};
  static_assert(std::size(display_names) == std::size(kDemoLogins));
  std::int64_t trainee_id = 0;
  std::int64_t resident_id = 0;
  std::int64_t instructor_id = 0;
  std::int64_t admin_id = 0;
  for (std::size_t i = 0; i < std::size(kDemoLogins); ++i) {
    const auto& login = kDemoLogins[i];
    const auto user = users.create(
        {login.username, display_names[i], *db::parse_role(login.role), login.password}, now);
    if (user.username == "trainee") trainee_id = user.id;
    if (user.username == "resident") resident_id = user.id;
    if (user.role == db::Role::instructor) instructor_id = user.id;
    if (user.role == db::Role::admin) admin_id = user.id;
  }
  users.set_instructors(trainee_id, {instructor_id}, now);
  users.set_instructors(resident_id, {instructor_id}, now);
  // Each station declares what it can run (the curriculum's tasks name the kind they need).
  const auto station = db::StationsRepo(db).create("Station 1", "Skills lab, room 2",
                                                   kDemoStationToken, now, "bench");
  db::StationsRepo(db).create(kDemoSurgicalStationName, "Skills lab, room 3: scalpel and grasper",
                              kDemoSurgicalStationToken, now, "laparoscopy");
  db::StationsRepo(db).create(kDemoArthroscopyStationName,
                              "Skills lab, room 4: arthroscope and probe at a knee model",
                              kDemoArthroscopyStationToken, now, "arthroscopy");

  // Validated by curriculum/ before it is stored, like every curriculum.
  const auto curriculum = curriculum::parse_curriculum_text(kDemoCurriculumJson);
  db::CurriculaRepo(db).create(curriculum.name, curriculum::to_json(curriculum).dump(), now);

  // One finished practice attempt from yesterday, marked as demo data by its task name.
  db::TrainingRepo training(db);
  const auto session = training.create_session(trainee_id, station.id, "palpation (demo)", now);
  training.set_session_state(session, "running", now - 86400);
  training.set_session_state(session, "finished", now - 86400 + 95);
  training.add_recording(session, 95.0, now - 86400 + 95);
  training.add_score(session, "completion_time_s", 95.0, "s", true, now - 86400 + 95);
  training.add_score(session, "path_length_m", 1.8, "m", false, now - 86400 + 95);
  training.add_score(session, "peak_force_n", 3.1, "N", true, now - 86400 + 95);

  // Rita has mastered the two palpation tasks over the last week (three passes in a row each,
  // every metric within its threshold), so the stations' tasks they unlock (the liver cut, the
  // knee tour) are open to her, a trainee partway through the course; Theo starts at the start.
  std::int64_t at = now - 7 * 86400;
  for (const char* key : {"palpation", "bimanual_palpation"}) {
    const curriculum::Task* task = curriculum::find_task(curriculum, key);
    for (int attempt = 0; attempt < task->consecutive_passes_required; ++attempt) {
      const auto id = training.create_session(resident_id, station.id, key, at);
      training.set_session_state(id, "running", at);
      training.set_session_state(id, "finished", at + 80);
      // Well within every threshold, better with each attempt.
      const auto scores = passing_scores(*task, 0.6 - 0.1 * attempt);
      training.add_scores(id, scores, at + 80);
      at += 86400;
    }
  }
  // The instructor's expert runs of the tasks with a station in the demo, three each and better
  // than any trainee, marked expert by the admin: the experts' band in every chart and result.
  db::ReviewsRepo reviews(db);
  for (const auto& module : curriculum.modules) {
    for (const auto& task : module.tasks) {
      for (int run = 0; run < 3; ++run) {
        const auto id = training.create_session(instructor_id, std::nullopt, task.key, at);
        training.set_session_state(id, "running", at);
        training.set_session_state(id, "finished", at + 60);
        training.add_scores(id, passing_scores(task, 0.15 + 0.05 * run), at + 60);
        reviews.set_expert_run(id, true, admin_id, at + 60);
        at += 600;
      }
    }
  }
  tx.commit();
  return true;
}

}  // namespace incise::server
