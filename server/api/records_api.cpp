#include "db/curricula_repo.h"
#include "db/training_repo.h"
#include "server/api/handlers.h"
#include "server/api/json_views.h"

namespace incise::server::api {

namespace {
// Trainees see only their own records; instructors and admins see everyone's.
std::optional<std::int64_t> visible_trainee(ApiContext& ctx) {
  const auto& user = ctx.user();
  return user.role == db::Role::trainee ? std::optional(user.id) : std::nullopt;
}

template <class Records>
ApiResponse as_list(const Records& records) {
  auto out = nlohmann::json::array();
  for (const auto& r : records)
    out.push_back(to_json(r));
  return {http::status::ok, out, {}};
}
}  // namespace

ApiResponse list_sessions(ApiContext& ctx) {
  return as_list(db::TrainingRepo(ctx.app.db()).sessions(visible_trainee(ctx)));
}

ApiResponse list_recordings(ApiContext& ctx) {
  return as_list(db::TrainingRepo(ctx.app.db()).recordings(visible_trainee(ctx)));
}

ApiResponse list_scores(ApiContext& ctx) {
  return as_list(db::TrainingRepo(ctx.app.db()).scores(visible_trainee(ctx)));
}

ApiResponse list_curricula(ApiContext& ctx) {
  ctx.user();
  return as_list(db::CurriculaRepo(ctx.app.db()).list());
}

}  // namespace incise::server::api
