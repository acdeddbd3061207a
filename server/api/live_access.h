#pragma once
// Who may see and control a session: its trainee, the trainee's instructors and admins
// (docs/api.md); and the curriculum task a session ran.
#include <optional>
#include <string>

#include "curriculum/curriculum.h"
#include "curriculum/progress.h"
#include "db/trainee_scope.h"
#include "db/training_repo.h"
#include "db/users_repo.h"
#include "server/api/api_context.h"

namespace incise::server::api {

// Whose records #user sees: a trainee their own, an instructor their own and
// their trainees' (trainee_instructors), an admin everyone's.
db::TraineeScope visible_scope(const db::User& user);

// True if #user may see the records of user #trainee_id (see visible_scope).
bool may_see_trainee(db::Database& db, const db::User& user, std::int64_t trainee_id);

// Whether #user may switch a session's picture from the scope to the view from outside the body:
// instructors and admins, watching or reviewing; a trainee trains with what the scope shows.
bool may_look_outside(const db::User& user);

// Throws ApiError 403 unless user may see the session.
void check_session_access(db::Database& db, const db::User& user, const db::SessionRecord& session);

// The session of the request's path id, which the caller may see. Throws ApiError 404 for no such
// session, 403 as check_session_access does.
db::SessionRecord visible_session(ApiContext& ctx);

// The curriculum task with this key, from the first curriculum that has it.
std::optional<curriculum::Task> find_curriculum_task(db::Database& db, const std::string& key);

// The scene text with the named material's constants (live/scene_material.h), for a session of a
// task that names one and its replay. Throws ApiError `status`, "<prefix>material \"X\", which
// does not exist" (or why it does not fit the scene).
std::string scene_text_with_material(db::Database& db, std::string_view scene_id,
                                     std::string_view scene_text, const std::string& material,
                                     http::status status, const std::string& prefix);

// The curriculum sessions run: the first one stored (docs/api.md, "Live sessions"); none when no
// curriculum is stored.
std::optional<curriculum::Curriculum> session_curriculum(db::Database& db);

// The first curriculum that has the task with this key.
std::optional<curriculum::Curriculum> curriculum_with_task(db::Database& db,
                                                           const std::string& key);

// The trainee's sessions as the progress rules read them (curriculum/progress.h), oldest first:
// task, whether finished, each score's pass, the latest adjustment.
std::vector<curriculum::AttemptRecord> attempt_records(db::Database& db, std::int64_t trainee_id);

// Whether the session passed as an attempt (curriculum::attempt_passed: its scores, or the latest
// adjustment); nullopt while it is not a finished, scored attempt.
std::optional<bool> session_passed(db::Database& db, const db::SessionRecord& session);

}  // namespace incise::server::api
