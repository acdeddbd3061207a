#include "server/api/live_access.h"

#include "curriculum/curriculum_json.h"
#include "db/curricula_repo.h"
#include "server/api/api_error.h"

namespace incise::server::api {

void check_session_access(const db::User& user, const db::SessionRecord& session) {
  if (user.role == db::Role::trainee && session.trainee_id != user.id) {
    throw ApiError(boost::beast::http::status::forbidden,
                   "session " + std::to_string(session.id) + " belongs to another trainee");
  }
}

db::SessionRecord visible_session(ApiContext& ctx) {
  const auto record = db::TrainingRepo(ctx.app.db()).find_session(ctx.path_id);
  if (!record) {
    throw ApiError(boost::beast::http::status::not_found,
                   "session " + std::to_string(ctx.path_id) + " does not exist");
  }
  check_session_access(ctx.user(), *record);
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
