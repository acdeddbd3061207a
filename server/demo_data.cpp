#include "server/demo_data.h"

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
  const char* display_names[] = {"Ada Admin", "Ines Instructor", "Theo Trainee"};
  std::int64_t trainee_id = 0;
  std::int64_t instructor_id = 0;
  for (std::size_t i = 0; i < std::size(kDemoLogins); ++i) {
    const auto& login = kDemoLogins[i];
    const auto user = users.create(
        {login.username, display_names[i], *db::parse_role(login.role), login.password}, now);
    if (user.role == db::Role::trainee) trainee_id = user.id;
    if (user.role == db::Role::instructor) instructor_id = user.id;
  }
  users.set_instructors(trainee_id, {instructor_id}, now);
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
  tx.commit();
  return true;
}

}  // namespace incise::server
