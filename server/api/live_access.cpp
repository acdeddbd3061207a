#include "server/api/live_access.h"

#include "curriculum/curriculum_json.h"
#include "db/curricula_repo.h"
#include "server/api/api_error.h"

namespace incise::server::api {

db::TraineeScope visible_scope(const db::User& user) {
  switch (user.role) {
    case db::Role::trainee:
      return db::TraineeScope::of_trainee(user.id);
    case db::Role::instructor:
      return db::TraineeScope::of_instructor(user.id);
    case db::Role::admin:
      break;
  }
  return db::TraineeScope::everyone();
}

bool may_see_trainee(db::Database& db, const db::User& user, std::int64_t trainee_id) {
  if (user.role == db::Role::admin || user.id == trainee_id) return true;
  return user.role == db::Role::instructor && db::UsersRepo(db).teaches(user.id, trainee_id);
}

bool may_look_outside(const db::User& user) {
  return user.role != db::Role::trainee;
}

void check_session_access(db::Database& db, const db::User& user,
                          const db::SessionRecord& session) {
  if (may_see_trainee(db, user, session.trainee_id)) return;
  throw ApiError(
      boost::beast::http::status::forbidden,
      "session " + std::to_string(session.id) + " belongs to " +
          (user.role == db::Role::trainee ? "another trainee" : "a trainee you do not teach"));
}

db::SessionRecord visible_session(ApiContext& ctx) {
  const auto record = db::TrainingRepo(ctx.app.db()).find_session(ctx.path_id);
  if (!record) {
    throw ApiError(boost::beast::http::status::not_found,
                   "session " + std::to_string(ctx.path_id) + " does not exist");
  }
  check_session_access(ctx.app.db(), ctx.user(), *record);
  return *record;
}

std::optional<curriculum::Task> find_curriculum_task(db::Database& db, const std::string& key) {
  for (const auto& record : db::CurriculaRepo(db).list()) {
    const auto c = curriculum::parse_curriculum_text(record.definition_json);
    if (const auto* task = curriculum::find_task(c, key)) return *task;
  }
  return std::nullopt;
}

}  // namespace incise::server::api
