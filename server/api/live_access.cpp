#include "server/api/live_access.h"

#include <algorithm>
#include <map>

#include "curriculum/curriculum_json.h"
#include "db/calibration_repo.h"
#include "db/curricula_repo.h"
#include "db/reviews_repo.h"
#include "server/api/api_error.h"
#include "server/live/scene_material.h"

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
  const auto record = db::TrainingRepo(ctx.db()).find_session(ctx.path_id);
  if (!record) {
    throw ApiError(boost::beast::http::status::not_found,
                   "session " + std::to_string(ctx.path_id) + " does not exist");
  }
  check_session_access(ctx.db(), ctx.user(), *record);
  return *record;
}

std::optional<curriculum::Curriculum> session_curriculum(db::Database& db) {
  const auto curricula = db::CurriculaRepo(db).list();
  if (curricula.empty()) return std::nullopt;
  return curriculum::parse_curriculum_text(curricula.front().definition_json);
}

std::optional<curriculum::Curriculum> curriculum_with_task(db::Database& db,
                                                           const std::string& key) {
  for (const auto& record : db::CurriculaRepo(db).list()) {
    auto c = curriculum::parse_curriculum_text(record.definition_json);
    if (curriculum::find_task(c, key) != nullptr) return c;
  }
  return std::nullopt;
}

std::vector<curriculum::AttemptRecord> attempt_records(db::Database& db, std::int64_t trainee_id) {
  db::TrainingRepo training(db);
  std::map<std::int64_t, std::vector<bool>> scores;
  for (const auto& score : training.scores(trainee_id))
    scores[score.session_id].push_back(score.passed);
  std::map<std::int64_t, bool> adjusted;
  for (const auto& adjustment : db::ReviewsRepo(db).latest_adjustments(trainee_id))
    adjusted[adjustment.session_id] = adjustment.passed;
  auto sessions = training.sessions(trainee_id);  // newest first
  std::reverse(sessions.begin(), sessions.end());
  std::vector<curriculum::AttemptRecord> out;
  for (const auto& s : sessions) {
    curriculum::AttemptRecord a;
    a.task = s.task;
    a.finished = s.state == "finished";
    if (const auto it = scores.find(s.id); it != scores.end()) a.scores = it->second;
    if (const auto it = adjusted.find(s.id); it != adjusted.end()) a.adjusted = it->second;
    out.push_back(std::move(a));
  }
  return out;
}

std::optional<bool> session_passed(db::Database& db, const db::SessionRecord& session) {
  curriculum::AttemptRecord attempt;
  attempt.task = session.task;
  attempt.finished = session.state == "finished";
  for (const auto& score : db::TrainingRepo(db).session_scores(session.id))
    attempt.scores.push_back(score.passed);
  if (const auto adjustments = db::ReviewsRepo(db).adjustments(session.id); !adjustments.empty())
    attempt.adjusted = adjustments.back().passed;
  if (!attempt.finished || (attempt.scores.empty() && !attempt.adjusted)) return std::nullopt;
  return curriculum::attempt_passed(attempt);
}

std::optional<curriculum::Task> find_curriculum_task(db::Database& db, const std::string& key) {
  const auto c = curriculum_with_task(db, key);
  if (!c) return std::nullopt;
  return *curriculum::find_task(*c, key);
}

std::string scene_text_with_material(db::Database& db, std::string_view scene_id,
                                     std::string_view scene_text, const std::string& material,
                                     http::status status, const std::string& prefix) {
  const auto found = db::MaterialsRepo(db).find_by_name(material);
  if (!found) {
    throw ApiError(status, prefix + "material \"" + material + "\", which does not exist");
  }
  try {
    return live::scene_with_material(scene_id, scene_text, found->constants, found->model);
  } catch (const std::invalid_argument& e) {
    throw ApiError(status, prefix + "material \"" + material + "\": " + e.what());
  }
}

}  // namespace incise::server::api
