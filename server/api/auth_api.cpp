#include "db/auth_sessions_repo.h"
#include "db/password.h"
#include "db/statement.h"
#include "db/transaction.h"
#include "db/users_repo.h"
#include "server/api/api_error.h"
#include "server/api/audit_change.h"
#include "server/api/handlers.h"
#include "server/api/json_views.h"
#include "server/api/request_fields.h"

namespace incise::server::api {

namespace {
// A browser-session cookie (no Max-Age): the server enforces the inactivity expiry, so an active
// person is never logged out by a cookie that was dated at login. `clear` deletes the cookie.
// Secure whenever the browser reached us over TLS (directly or through the trusted proxy), or
// always with --secure-cookies.
std::string session_cookie(const ApiContext& ctx, const std::string& token, bool clear) {
  std::string c = std::string(kSessionCookie) + "=" + token + "; Path=/; HttpOnly; SameSite=Strict";
  if (clear) c += "; Max-Age=0";
  if (ctx.https || ctx.app.config().secure_cookies) c += "; Secure";
  return c;
}
}  // namespace

ApiResponse health(ApiContext&) {
  return {http::status::ok, {{"status", "ok"}, {"version", "0.1.0"}}, {}};
}

ApiResponse ready(ApiContext& ctx) {
  // A load balancer sends no traffic to a node whose database is out of reach. The pool waits
  // for a free connection, so a busy node is still ready; a failed query is an ApiError's 503.
  try {
    ctx.db().prepare("SELECT 1").step();
  } catch (const std::exception& e) {
    throw ApiError(http::status::service_unavailable,
                   std::string("the database does not answer: ") + e.what());
  }
  return {http::status::ok, {{"status", "ready"}, {"node", ctx.app.config().node_id}}, {}};
}

namespace {
// 429 with Retry-After while the limiter holds `account` at this address back.
void check_login_limit(ApiContext& ctx, std::string_view account, std::string_view what) {
  const auto wait = ctx.app.login_limiter().retry_after(account, ctx.client, ctx.now);
  if (wait <= 0) return;
  throw ApiError(http::status::too_many_requests,
                 "too many " + std::string(what) + "; try again in " + std::to_string(wait) + " s",
                 {{"Retry-After", std::to_string(wait)}});
}

// Whether `password` matches `hash` ("" when there is no such user: the same work is spent). The
// check takes about 50 ms of argon2id; logins run on the password workers, not the I/O threads,
// so other requests go on meanwhile.
bool password_checks(std::string_view password, const std::string& hash) {
  if (hash.empty()) {
    db::spend_password_check(password);
    return false;
  }
  return db::verify_password(password, hash);
}
}  // namespace

ApiResponse login(ApiContext& ctx) {
  const auto body = ctx.json_body();
  const RequestFields fields(body, {"username", "password"});
  const auto username = fields.string("username");
  const auto password = fields.string("password");

  check_login_limit(ctx, username, "failed logins");
  db::UsersRepo users(ctx.db());
  const auto found = users.credentials(username);
  auto& limiter = ctx.app.login_limiter();
  if (!password_checks(password, found ? found->password_hash : std::string())) {
    limiter.record_failure(username, ctx.client, ctx.now);
    throw ApiError(http::status::unauthorized, "wrong username or password");
  }
  limiter.record_success(username, ctx.client, ctx.now);
  // Read again: the account may have changed while the password was checked.
  const auto user = users.find(found->user.id);
  if (!user) throw ApiError(http::status::unauthorized, "wrong username or password");
  // Said only to whoever knows the password, so it reveals nothing to a guesser.
  if (user->disabled_at) {
    throw ApiError(http::status::forbidden, "this account is disabled; ask an admin");
  }
  const auto ttl = ctx.app.config().session_ttl_s;
  const auto token = db::AuthSessionsRepo(ctx.db()).create(user->id, ctx.now, ttl);
  db::AuthSessionsRepo(ctx.db()).purge_expired(ctx.now);
  return {http::status::ok,
          {{"user", to_json(*user)}},
          {{"Set-Cookie", session_cookie(ctx, token, false)}}};
}

ApiResponse logout(ApiContext& ctx) {
  if (const auto token = ctx.cookie(kSessionCookie)) {
    db::AuthSessionsRepo(ctx.db()).remove(*token);
  }
  return {http::status::no_content, nullptr, {{"Set-Cookie", session_cookie(ctx, "", true)}}};
}

ApiResponse me(ApiContext& ctx) {
  return {http::status::ok, to_json(ctx.signed_in()), {}};
}

ApiResponse change_own_password(ApiContext& ctx) {
  const auto& user = ctx.signed_in();
  const auto body = ctx.json_body();
  const RequestFields fields(body, {"current_password", "new_password"});
  const auto current = fields.string("current_password");
  const auto next = fields.string("new_password");
  check_new_password("new_password", next, user.username);
  if (next == current) {
    throw ApiError(http::status::unprocessable_entity,
                   "new_password must differ from the current one");
  }
  auto& db = ctx.db();
  db::UsersRepo users(db);
  // A stolen cookie must not be able to take the account over, nor guess the password here
  // faster than at the login: the same limiter counts these failures.
  check_login_limit(ctx, user.username, "failed attempts");
  const std::string checked = users.password_hash(user.id);
  if (!password_checks(current, checked)) {
    ctx.app.login_limiter().record_failure(user.username, ctx.client, ctx.now);
    throw ApiError(http::status::unprocessable_entity, "current_password is wrong");
  }
  const db::PasswordHash hash = ctx.hash_password(next);
  db::Transaction tx(db);
  ctx.reread_user();  // `user` again: the login may have ended during the check and the hash
  // Both ran outside any transaction: an admin's reset (or another change) meanwhile wins.
  if (users.password_hash(user.id) != checked) {
    throw ApiError(http::status::conflict,
                   "your password was changed meanwhile; log in again and retry");
  }
  users.set_password(user.id, hash, false);
  // Every other login of theirs ends: whoever else held a cookie is out.
  db::AuthSessionsRepo(db).remove_others(user.id, ctx.cookie(kSessionCookie).value_or(""));
  audit_change(db, user.id, "user.password_change", user.username, ctx.now,
               {{"must_change_password", user.must_change_password}},
               {{"must_change_password", false}});
  tx.commit();
  return {http::status::ok, to_json(*users.find(user.id)), {}};
}

}  // namespace incise::server::api
