// A trainee's proficiency-based progression: per task of the curriculum the
// sessions run, the attempts, the current run of passes, whether it is mastered and whether it
// is unlocked (every prerequisite mastered). An attempt is a finished session of that task; it
// passed when every metric the task scores passed (curriculum/proficiency.h).

#include <algorithm>
#include <map>
#include <set>
#include <vector>

#include "curriculum/curriculum_json.h"
#include "curriculum/proficiency.h"
#include "db/curricula_repo.h"
#include "db/reviews_repo.h"
#include "db/training_repo.h"
#include "db/users_repo.h"
#include "server/api/api_error.h"
#include "server/api/handlers.h"
#include "server/api/live_access.h"

namespace incise::server::api {
namespace {

nlohmann::json progress_of(db::Database& db, std::int64_t trainee_id) {
  const auto curricula = db::CurriculaRepo(db).list();
  if (curricula.empty()) return {{"curriculum", nullptr}, {"tasks", nlohmann::json::array()}};
  // Sessions run the tasks of the first curriculum (docs/api.md, "Live sessions").
  const curriculum::Curriculum plan =
      curriculum::parse_curriculum_text(curricula.front().definition_json);

  db::TrainingRepo training(db);
  // Whether each session passed: it has scores and all of them passed.
  std::map<std::int64_t, bool> passed;
  for (const auto& score : training.scores(trainee_id)) {
    auto [it, fresh] = passed.try_emplace(score.session_id, score.passed);
    if (!fresh) it->second = it->second && score.passed;
  }
  // An instructor's adjustment overrides the computed result.
  for (const auto& adjustment : db::ReviewsRepo(db).latest_adjustments(trainee_id)) {
    passed[adjustment.session_id] = adjustment.passed;
  }
  // Finished attempts per task, oldest first (the repo lists newest first).
  auto sessions = training.sessions(trainee_id);
  std::reverse(sessions.begin(), sessions.end());
  std::map<std::string, std::vector<bool>> attempts;
  for (const auto& s : sessions) {
    if (s.state != "finished") continue;
    const auto it = passed.find(s.id);
    attempts[s.task].push_back(it != passed.end() && it->second);
  }

  std::set<std::string> mastered;
  for (const auto& module : plan.modules) {
    for (const auto& task : module.tasks) {
      if (curriculum::task_mastered(task, attempts[task.key])) mastered.insert(task.key);
    }
  }
  auto tasks = nlohmann::json::array();
  for (const auto& module : plan.modules) {
    for (const auto& task : module.tasks) {
      const auto& history = attempts[task.key];
      const bool unlocked =
          std::all_of(task.prerequisites.begin(), task.prerequisites.end(),
                      [&](const std::string& key) { return mastered.contains(key); });
      tasks.push_back({{"key", task.key},
                       {"name", task.name},
                       {"module", module.name},
                       {"prerequisites", task.prerequisites},
                       {"attempts", history.size()},
                       {"passed_attempts", std::count(history.begin(), history.end(), true)},
                       {"consecutive_passes", curriculum::consecutive_passes(history)},
                       {"required_passes", task.consecutive_passes_required},
                       {"mastered", mastered.contains(task.key)},
                       {"unlocked", unlocked}});
    }
  }
  return {{"trainee_id", trainee_id}, {"curriculum", plan.name}, {"tasks", std::move(tasks)}};
}

}  // namespace

ApiResponse my_progress(ApiContext& ctx) {
  return {http::status::ok, progress_of(ctx.app.db(), ctx.user().id)};
}

ApiResponse trainee_progress(ApiContext& ctx) {
  const auto& user = ctx.user();
  if (user.role == db::Role::trainee && user.id != ctx.path_id) {
    throw ApiError(http::status::forbidden, "trainees see only their own progress");
  }
  // Checked before the trainee is looked up, so that an instructor cannot tell an unknown id
  // from a trainee they do not teach.
  if (!may_see_trainee(ctx.app.db(), user, ctx.path_id)) {
    throw ApiError(http::status::forbidden,
                   "you do not teach trainee " + std::to_string(ctx.path_id));
  }
  const auto trainee = db::UsersRepo(ctx.app.db()).find(ctx.path_id);
  if (!trainee || trainee->role != db::Role::trainee) {
    throw ApiError(http::status::not_found,
                   "trainee " + std::to_string(ctx.path_id) + " does not exist");
  }
  return {http::status::ok, progress_of(ctx.app.db(), ctx.path_id)};
}

ApiResponse progress_overview(ApiContext& ctx) {
  const auto& viewer = ctx.require_role({db::Role::instructor, db::Role::admin});
  auto out = nlohmann::json::array();
  for (const auto& user : db::UsersRepo(ctx.app.db()).list()) {
    if (user.role != db::Role::trainee || !may_see_trainee(ctx.app.db(), viewer, user.id)) continue;
    auto row = progress_of(ctx.app.db(), user.id);
    row["username"] = user.username;
    row["display_name"] = user.display_name;
    out.push_back(std::move(row));
  }
  return {http::status::ok, std::move(out)};
}

}  // namespace incise::server::api
