#pragma once
// What one REST handler sees: the request, the app, the caller, and helpers that turn missing
// logins, wrong roles and malformed bodies into ApiErrors. ctx.db() is the request's own pooled
// connection, so handlers use the repositories directly; requests run side by side.
#include <boost/beast/http.hpp>
#include <cstdint>
#include <initializer_list>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "db/users_repo.h"
#include "server/app_state.h"

namespace incise::server {

namespace http = boost::beast::http;
using Request = http::request<http::string_body>;
using Response = http::response<http::string_body>;

struct ApiResponse {
  using Headers = std::vector<std::pair<std::string, std::string>>;
  ApiResponse() = default;
  ApiResponse(http::status status, nlohmann::json body, Headers headers = {})
      : status(status), body(std::move(body)), headers(std::move(headers)) {}

  http::status status = http::status::ok;
  nlohmann::json body;  // null for 204
  std::vector<std::pair<std::string, std::string>> headers;
  // A body that is not JSON (a CSV export): sent as it is with this Content-Type.
  std::optional<std::string> text_body;
  std::string content_type;
};

// Who sent a request: the client's address (behind a trusted proxy, the one it forwarded) and
// whether the browser reached us over TLS (server_options.h: reached_over_tls).
struct Caller {
  std::string address;
  bool https = false;
};

class ApiContext {
 public:
  ApiContext(const Request& request, AppState& app, Caller caller)
      : request(request),
        app(app),
        client(std::move(caller.address)),
        https(caller.https),
        now(app.now()) {}

  const Request& request;
  AppState& app;
  const std::string client;  // remote address, for the login limiter
  const bool https;          // over TLS: the login cookie is Secure
  const std::int64_t now;    // Unix seconds, fixed for the whole request
  std::int64_t path_id = 0;  // the {id} of the matched route, if any

  // This request's database connection, leased from the pool on first use and given back when
  // the request ends. Requests run side by side: an invariant that needs several statements to
  // hold together takes a db::Transaction (IMMEDIATE for read-check-write).
  db::Database& db() {
    if (!lease_) lease_.emplace(app.pool().acquire());
    return **lease_;
  }
  // password's stored form (db::hash_password: about 50 ms of argon2id), made before the
  // handler's transaction: inside it, the handler reads again what the change depends on
  // (reread_user(), the account), since either may have changed during the hash.
  db::PasswordHash hash_password(std::string_view password);
  // Reads the signed-in user again, in place (handlers hold references to it): 401 if their
  // login ended meanwhile. Inside a handler's transaction, so that a check of the caller (still
  // an admin? still enabled?) holds for the change it guards; check roles after this.
  void reread_user();

  // The logged-in user; throws 401 when there is none or the session expired, and 403 while
  // their password must be changed (an admin reset it): then only signed_in() callers answer.
  const db::User& user();
  // The logged-in user even while their password must be changed (GET /api/me, choosing the
  // new password); 401 when there is none.
  const db::User& signed_in();
  // The logged-in user if their role is one of `roles`; 403 otherwise.
  const db::User& require_role(std::initializer_list<db::Role> roles);
  // The parsed JSON body; 400 for malformed JSON (invalid UTF-8 and lone surrogates included, and
  // nesting deeper than kMaxJsonDepth), 422 for a number beyond a double's range.
  nlohmann::json json_body() const;
  std::optional<std::string> cookie(std::string_view name) const;

 private:
  std::optional<db::User> user_;
  std::optional<db::ConnectionPool::Lease> lease_;
};

inline constexpr const char* kSessionCookie = "incise_session";

}  // namespace incise::server
