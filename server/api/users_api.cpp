#include <algorithm>

#include "db/audit_repo.h"
#include "server/api/api_error.h"
#include "server/api/handlers.h"
#include "server/api/json_views.h"
#include "server/api/request_fields.h"

namespace incise::server::api {

namespace {
void check_username(const std::string& name) {
  const bool ok =
      name.size() >= 3 && name.size() <= 32 && std::all_of(name.begin(), name.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' || c == '_' || c == '-';
      });
  if (!ok) {
    throw ApiError(http::status::unprocessable_entity,
                   "username must be 3-32 characters of a-z, 0-9, '.', '_' or '-'");
  }
}
}  // namespace

ApiResponse list_users(ApiContext& ctx) {
  ctx.require_role({db::Role::admin});
  auto out = nlohmann::json::array();
  for (const auto& u : db::UsersRepo(ctx.app.db()).list())
    out.push_back(to_json(u));
  return {http::status::ok, out, {}};
}

ApiResponse create_user(ApiContext& ctx) {
  const auto& admin = ctx.require_role({db::Role::admin});
  const auto body = ctx.json_body();
  const RequestFields fields(body, {"username", "password", "role", "display_name"});
  db::NewUser user;
  user.username = fields.string("username");
  check_username(user.username);
  user.display_name = fields.string_or("display_name", user.username);
  if (user.display_name.empty() || user.display_name.size() > 80) {
    throw ApiError(http::status::unprocessable_entity, "display_name must be 1-80 characters");
  }
  const auto role_text = fields.string("role");
  const auto role = db::parse_role(role_text);
  if (!role) {
    throw ApiError(http::status::unprocessable_entity,
                   "role must be trainee, instructor or admin (got '" + role_text + "')");
  }
  user.role = *role;
  user.password = fields.string("password");
  if (user.password.size() < 10) {
    throw ApiError(http::status::unprocessable_entity, "password must have at least 10 characters");
  }
  if (user.password.size() > 256) {
    throw ApiError(http::status::unprocessable_entity, "password must have at most 256 characters");
  }
  const auto created = db::UsersRepo(ctx.app.db()).create(user, ctx.now);
  db::AuditRepo(ctx.app.db())
      .record(admin.id, "user.create",
              created.username + " (" + std::string(db::to_string(created.role)) + ")", ctx.now);
  return {http::status::created, to_json(created), {}};
}

}  // namespace incise::server::api
