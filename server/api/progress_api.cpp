// A trainee's proficiency-based progression: per task of the curriculum the attempts, the current
// run of passes, whether it is mastered and whether it is unlocked, with what locks it. The rules
// are curriculum/progress.h's; this serialises them.

#include "curriculum/progress.h"
#include "db/users_repo.h"
#include "server/api/api_error.h"
#include "server/api/handlers.h"
#include "server/api/live_access.h"

namespace incise::server::api {
namespace {

nlohmann::json progress_of(db::Database& db, std::int64_t trainee_id) {
  const auto session_plan = session_curriculum(db);
  if (!session_plan) {
    return {{"curriculum", nullptr}, {"tasks", nlohmann::json::array()}, {"next_task", nullptr}};
  }
  const curriculum::Curriculum& plan = *session_plan;
  auto tasks = nlohmann::json::array();
  const auto progress = curriculum::curriculum_progress(plan, attempt_records(db, trainee_id));
  for (const auto& p : progress) {
    const curriculum::Task& task = *curriculum::find_task(plan, p.key);
    tasks.push_back({{"key", p.key},
                     {"name", task.name},
                     {"module", p.module},
                     {"prerequisites", task.prerequisites},
                     {"attempts", p.attempts},
                     {"passed_attempts", p.passed_attempts},
                     {"consecutive_passes", p.consecutive_passes},
                     {"required_passes", p.required_passes},
                     {"mastered", p.mastered},
                     {"unlocked", p.unlocked()},
                     {"missing_prerequisites", p.missing_prerequisites},
                     {"locked_reason", curriculum::locked_reason(plan, p)}});
  }
  const auto next = curriculum::next_task(progress);
  return {{"trainee_id", trainee_id},
          {"curriculum", plan.name},
          {"tasks", std::move(tasks)},
          {"next_task", next.empty() ? nlohmann::json(nullptr) : nlohmann::json(next)}};
}

}  // namespace

ApiResponse my_progress(ApiContext& ctx) {
  return {http::status::ok, progress_of(ctx.db(), ctx.user().id)};
}

ApiResponse trainee_progress(ApiContext& ctx) {
  const auto& user = ctx.user();
  if (user.role == db::Role::trainee && user.id != ctx.path_id) {
    throw ApiError(http::status::forbidden, "trainees see only their own progress");
  }
  // Checked before the trainee is looked up, so that an instructor cannot tell an unknown id
  // from a trainee they do not teach.
  if (!may_see_trainee(ctx.db(), user, ctx.path_id)) {
    throw ApiError(http::status::forbidden,
                   "you do not teach trainee " + std::to_string(ctx.path_id));
  }
  const auto trainee = db::UsersRepo(ctx.db()).find(ctx.path_id);
  if (!trainee || trainee->role != db::Role::trainee) {
    throw ApiError(http::status::not_found,
                   "trainee " + std::to_string(ctx.path_id) + " does not exist");
  }
  return {http::status::ok, progress_of(ctx.db(), ctx.path_id)};
}

ApiResponse progress_overview(ApiContext& ctx) {
  const auto& viewer = ctx.require_role({db::Role::instructor, db::Role::admin});
  auto out = nlohmann::json::array();
  for (const auto& user : db::UsersRepo(ctx.db()).list()) {
    if (user.role != db::Role::trainee || !may_see_trainee(ctx.db(), viewer, user.id)) continue;
    auto row = progress_of(ctx.db(), user.id);
    row["username"] = user.username;
    row["display_name"] = user.display_name;
    out.push_back(std::move(row));
  }
  return {http::status::ok, std::move(out)};
}

}  // namespace incise::server::api
