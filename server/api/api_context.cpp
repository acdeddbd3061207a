#include "server/api/api_context.h"

#include <algorithm>

#include "db/auth_sessions_repo.h"
#include "db/password.h"
#include "server/api/api_error.h"
#include "server/json_input.h"

namespace incise::server {

db::PasswordHash ApiContext::hash_password(std::string_view password) {
  db::PasswordHash hash;
  hash.value = db::hash_password(password);
  return hash;
}

void ApiContext::reread_user() {
  const auto token = cookie(kSessionCookie);
  auto fresh = token ? db::AuthSessionsRepo(db()).touch(*token, now, app.config().session_ttl_s)
                     : std::nullopt;
  if (!fresh) {
    throw ApiError(http::status::unauthorized, "not logged in (the session has ended or expired)");
  }
  if (user_) {
    *user_ = std::move(*fresh);
  } else {
    user_ = std::move(fresh);
  }
}

const db::User& ApiContext::user() {
  const auto& u = signed_in();
  if (u.must_change_password) {
    throw ApiError(http::status::forbidden,
                   "choose a new password first: an admin reset yours (POST /api/me/password)");
  }
  return u;
}

const db::User& ApiContext::signed_in() {
  if (user_) return *user_;
  const auto token = cookie(kSessionCookie);
  if (!token) throw ApiError(http::status::unauthorized, "not logged in");
  user_ = db::AuthSessionsRepo(db()).touch(*token, now, app.config().session_ttl_s);
  if (!user_)
    throw ApiError(http::status::unauthorized, "not logged in (the session has ended or expired)");
  return *user_;
}

const db::User& ApiContext::require_role(std::initializer_list<db::Role> roles) {
  const auto& u = user();
  if (std::find(roles.begin(), roles.end(), u.role) == roles.end()) {
    std::string allowed;
    for (auto r : roles)
      allowed += (allowed.empty() ? "" : " or ") + std::string(db::to_string(r));
    throw ApiError(http::status::forbidden, "this needs the role " + allowed + " (you are " +
                                                std::string(db::to_string(u.role)) + ")");
  }
  return u;
}

nlohmann::json ApiContext::json_body() const {
  auto input = parse_json_input(request.body());
  switch (input.error) {
    case JsonInputError::none:
      return std::move(input.value);
    case JsonInputError::out_of_range:
      // Well-formed JSON whose value cannot be represented: like any other invalid field.
      throw ApiError(http::status::unprocessable_entity, "number out of range: " + input.message);
    case JsonInputError::syntax:
    case JsonInputError::too_deep:
      break;
  }
  throw ApiError(http::status::bad_request, "malformed JSON: " + input.message);
}

std::optional<std::string> ApiContext::cookie(std::string_view name) const {
  const auto header = request[http::field::cookie];
  std::string_view rest(header.data(), header.size());
  while (!rest.empty()) {
    const auto end = rest.find(';');
    auto pair = rest.substr(0, end);
    rest = end == std::string_view::npos ? std::string_view{} : rest.substr(end + 1);
    while (!pair.empty() && pair.front() == ' ')
      pair.remove_prefix(1);
    const auto eq = pair.find('=');
    if (eq != std::string_view::npos && pair.substr(0, eq) == name) {
      return std::string(pair.substr(eq + 1));
    }
  }
  return std::nullopt;
}

}  // namespace incise::server
