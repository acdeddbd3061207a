#include "db/auth_sessions_repo.h"
#include "server/api/api_error.h"
#include "server/api/handlers.h"
#include "server/api/json_views.h"
#include "server/api/request_fields.h"

namespace incise::server::api {

namespace {
// A browser-session cookie (no Max-Age): the server enforces the inactivity expiry, so an active
// person is never logged out by a cookie that was dated at login. `clear` deletes the cookie.
std::string session_cookie(const AppState& app, const std::string& token, bool clear) {
  std::string c = std::string(kSessionCookie) + "=" + token + "; Path=/; HttpOnly; SameSite=Strict";
  if (clear) c += "; Max-Age=0";
  if (app.config().secure_cookies) c += "; Secure";
  return c;
}
}  // namespace

ApiResponse health(ApiContext&) {
  return {http::status::ok, {{"status", "ok"}, {"version", "0.1.0"}}, {}};
}

ApiResponse login(ApiContext& ctx) {
  const auto body = ctx.json_body();
  const RequestFields fields(body, {"username", "password"});
  const auto username = fields.string("username");
  const auto password = fields.string("password");

  auto& limiter = ctx.app.login_limiter();
  if (const auto wait = limiter.retry_after(ctx.client, ctx.now); wait > 0) {
    throw ApiError(http::status::too_many_requests,
                   "too many failed logins; try again in " + std::to_string(wait) + " s");
  }
  const auto user = db::UsersRepo(ctx.app.db()).authenticate(username, password);
  if (!user) {
    limiter.record_failure(ctx.client, ctx.now);
    throw ApiError(http::status::unauthorized, "wrong username or password");
  }
  limiter.record_success(ctx.client);
  const auto ttl = ctx.app.config().session_ttl_s;
  const auto token = db::AuthSessionsRepo(ctx.app.db()).create(user->id, ctx.now, ttl);
  db::AuthSessionsRepo(ctx.app.db()).purge_expired(ctx.now);
  return {http::status::ok,
          {{"user", to_json(*user)}},
          {{"Set-Cookie", session_cookie(ctx.app, token, false)}}};
}

ApiResponse logout(ApiContext& ctx) {
  if (const auto token = ctx.cookie(kSessionCookie)) {
    db::AuthSessionsRepo(ctx.app.db()).remove(*token);
  }
  return {http::status::no_content, nullptr, {{"Set-Cookie", session_cookie(ctx.app, "", true)}}};
}

ApiResponse me(ApiContext& ctx) {
  return {http::status::ok, to_json(ctx.user()), {}};
}

}  // namespace incise::server::api
