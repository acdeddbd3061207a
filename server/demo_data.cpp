#include "server/demo_data.h"

#include <algorithm>
#include <cmath>

#include "curriculum/curriculum_json.h"
#include "db/curricula_repo.h"
#include "db/stations_repo.h"
#include "db/training_repo.h"
#include "db/transaction.h"
#include "db/users_repo.h"

namespace incise::server {

// Generated from curriculum/demo/basic_skills.json at build time.
extern const char* const kDemoCurriculumJson;

bool seed_demo_data(db::Database& db, std::int64_t now) {
  db::UsersRepo users(db);
  if (users.count() > 0) return false;
  db::Transaction tx(db);
  const char* display_names[] = {"Ada Admin", "Ines Instructor", "Theo Trainee", "Rita Resident"};
  static_assert(std::size(display_names) == std::size(kDemoLogins));
  std::int64_t trainee_id = 0;
  std::int64_t resident_id = 0;
  std::int64_t instructor_id = 0;
  for (std::size_t i = 0; i < std::size(kDemoLogins); ++i) {
    const auto& login = kDemoLogins[i];
    const auto user = users.create(
        {login.username, display_names[i], *db::parse_role(login.role), login.password}, now);
    if (user.username == "trainee") trainee_id = user.id;
    if (user.username == "resident") resident_id = user.id;
    if (user.role == db::Role::instructor) instructor_id = user.id;
  }
  users.set_instructors(trainee_id, {instructor_id}, now);
  users.set_instructors(resident_id, {instructor_id}, now);
  const auto station =
      db::StationsRepo(db).create("Station 1", "Skills lab, room 2", kDemoStationToken, now);
  db::StationsRepo(db).create(kDemoSurgicalStationName, "Skills lab, room 3: scalpel and grasper",
                              kDemoSurgicalStationToken, now);
  db::StationsRepo(db).create(kDemoArthroscopyStationName,
                              "Skills lab, room 4: arthroscope and probe at a knee model",
                              kDemoArthroscopyStationToken, now);

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
      for (const auto& metric : task->metrics) {
        // Well within the threshold, better with each attempt; counts whole, fractions at most 1.
        const double limit = metric.threshold.value;
        double value = 0;
        if (metric.threshold.op == curriculum::ThresholdOp::at_most) {
          value = limit * (0.6 - 0.1 * attempt);
          if (metric.unit == "count") value = std::floor(value);
        } else {
          value = limit * (1.2 + 0.1 * attempt);
          if (metric.unit.empty() && limit <= 1) value = std::min(value, 1.0);
        }
        value = std::round(value * 1000) / 1000;  // as a person would read them
        training.add_score(id, metric.key, value, metric.unit, true, at + 80);
      }
      at += 86400;
    }
  }
  tx.commit();
  return true;
}

}  // namespace incise::server
