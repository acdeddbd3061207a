// Logins, sessions and their expiry: server/api/auth_api.cpp through the router.
#include <gtest/gtest.h>

#include <string>

#include "api_test_app.h"
#include "server/demo_data.h"

namespace incise::server::test {
namespace {

class AuthApi : public ApiTest {
 protected:
  Response login(const std::string& username, const std::string& password,
                 const std::string& client = kClient) {
    Call c{http::verb::post, "/api/login",
           nlohmann::json{{"username", username}, {"password", password}}.dump()};
    c.client = client;
    return call(c);
  }

  // The session token of a Set-Cookie header value.
  static std::string token_of(const Response& response) {
    const std::string cookie(response[http::field::set_cookie]);
    const std::string prefix = std::string(kSessionCookie) + "=";
    if (cookie.rfind(prefix, 0) != 0) return "";
    return cookie.substr(prefix.size(), cookie.find(';') - prefix.size());
  }

  std::int64_t ttl() { return app().config().session_ttl_s; }
};

TEST_F(AuthApi, LoginSetsASessionCookie) {
  const auto response = login("instructor", "incise-instructor-demo");
  ASSERT_EQ(response.result(), http::status::ok) << response.body();
  const auto body = json_of(response);
  EXPECT_EQ(body["user"]["username"], "instructor");
  EXPECT_EQ(body["user"]["role"], "instructor");
  EXPECT_EQ(body["user"]["display_name"], "Ines Instructor");
  EXPECT_TRUE(body["user"]["id"].is_number_integer());
  EXPECT_FALSE(body["user"].contains("password_hash"));

  const std::string cookie(response[http::field::set_cookie]);
  EXPECT_NE(cookie.find("; HttpOnly"), std::string::npos) << cookie;
  EXPECT_NE(cookie.find("; SameSite=Strict"), std::string::npos) << cookie;
  EXPECT_NE(cookie.find("; Path=/"), std::string::npos) << cookie;
  EXPECT_EQ(cookie.find("Secure"), std::string::npos) << cookie;   // no TLS here
  EXPECT_EQ(cookie.find("Max-Age"), std::string::npos) << cookie;  // a browser-session cookie
  EXPECT_EQ(cookie.find("Expires"), std::string::npos) << cookie;
  const auto token = token_of(response);
  EXPECT_EQ(token.size(), 64u) << cookie;

  const auto me = get("/api/me", token);
  ASSERT_EQ(me.result(), http::status::ok);
  EXPECT_EQ(json_of(me), body["user"]);
}

TEST_F(AuthApi, WrongPasswordOrUnknownUser) {
  const auto sessions = count("auth_sessions");
  for (const auto& [user, password] :
       {std::pair{"trainee", "incise-admin-demo"}, std::pair{"trainee", ""},
        std::pair{"nobody", "whatever1234"}, std::pair{"TRAINEE", "incise-trainee-demo"}}) {
    const auto response = login(user, password);
    EXPECT_TRUE(is_error(response, http::status::unauthorized, "wrong username or password"))
        << user;
    EXPECT_EQ(response[http::field::set_cookie], "") << user;
  }
  EXPECT_EQ(count("auth_sessions"), sessions);
}

TEST_F(AuthApi, LoginBodiesAreValidated) {
  Call c{http::verb::post, "/api/login", R"({"username": "trainee"})"};
  EXPECT_TRUE(is_error(call(c), http::status::unprocessable_entity, "missing field 'password'"));
  c.body = R"({"username": "trainee", "password": 5})";
  EXPECT_TRUE(
      is_error(call(c), http::status::unprocessable_entity, "field 'password' must be a string"));
  c.body = R"({"username": "trainee", "password": "incise-trainee-demo", "remember": true})";
  EXPECT_TRUE(is_error(call(c), http::status::unprocessable_entity, "unknown field 'remember'"));
  c.body = R"({"username": "trainee", "password": )";
  EXPECT_TRUE(is_error(call(c), http::status::bad_request));
}

TEST_F(AuthApi, LogoutEndsTheSession) {
  const auto token = session_of(Who::trainee);
  ASSERT_EQ(get("/api/me", token).result(), http::status::ok);
  const auto response = post("/api/logout", nlohmann::json::object(), token);
  EXPECT_EQ(response.result(), http::status::no_content);
  const std::string cookie(response[http::field::set_cookie]);
  EXPECT_EQ(cookie.rfind(std::string(kSessionCookie) + "=;", 0), 0u) << cookie;
  EXPECT_NE(cookie.find("Max-Age=0"), std::string::npos) << cookie;
  EXPECT_TRUE(is_error(get("/api/me", token), http::status::unauthorized,
                       "not logged in (the session has ended or expired)"));
}

TEST_F(AuthApi, UnknownTokensAreRefused) {
  EXPECT_TRUE(is_error(get("/api/me", std::string(64, 'a')), http::status::unauthorized,
                       "not logged in (the session has ended or expired)"));
  EXPECT_TRUE(is_error(get("/api/me", ""), http::status::unauthorized, "not logged in"));
}

TEST_F(AuthApi, AnIdleSessionExpiresAfterTheTtl) {
  EXPECT_EQ(ttl(), 12 * 3600);  // docs/api.md
  const auto token = session_of(Who::trainee);
  set_now(kStart + ttl() - 1);
  const auto still = session_of(Who::instructor);  // created later, to stay alive
  set_now(kStart + ttl());
  EXPECT_TRUE(is_error(get("/api/me", token), http::status::unauthorized,
                       "not logged in (the session has ended or expired)"));
  EXPECT_EQ(get("/api/me", still).result(), http::status::ok);
}

TEST_F(AuthApi, ActivityKeepsASessionAlive) {
  const auto token = session_of(Who::trainee);
  std::int64_t t = kStart;
  // Four requests, each just before the previous one's expiry: four TTLs in all.
  for (int i = 0; i < 4; ++i) {
    t += ttl() - 1;
    set_now(t);
    ASSERT_EQ(get("/api/bookings", token).result(), http::status::ok) << i;
  }
  set_now(t + ttl());
  EXPECT_TRUE(is_error(get("/api/me", token), http::status::unauthorized,
                       "not logged in (the session has ended or expired)"));
}

TEST_F(AuthApi, RepeatedFailuresWaitWithRetryAfterAndOnlyThatAccountAtThatAddress) {
  const LoginPolicy policy;
  for (int i = 0; i <= policy.free_per_pair; ++i) {
    ASSERT_EQ(login("trainee", "wrong password", "192.0.2.66").result(), http::status::unauthorized)
        << i;
  }
  // Even the right password waits: the limiter is asked before the password is checked.
  const auto held = login("trainee", "incise-trainee-demo", "192.0.2.66");
  EXPECT_TRUE(
      is_error(held, http::status::too_many_requests, "too many failed logins; try again in 1 s"));
  EXPECT_EQ(held[http::field::retry_after], "1");
  // Another address, and another account from this one, are not held.
  EXPECT_EQ(login("trainee", "incise-trainee-demo", "192.0.2.67").result(), http::status::ok);
  EXPECT_EQ(login("admin", "incise-admin-demo", "192.0.2.66").result(), http::status::ok);
  set_now(kStart + 1);
  EXPECT_EQ(login("trainee", "incise-trainee-demo", "192.0.2.66").result(), http::status::ok);
}

class AuthApiBehindTls : public AuthApi {
 protected:
  AuthApiBehindTls() { config_.secure_cookies = true; }
};

TEST_F(AuthApiBehindTls, CookiesAreSecure) {
  const auto response = login("admin", "incise-admin-demo");
  ASSERT_EQ(response.result(), http::status::ok);
  EXPECT_NE(std::string(response[http::field::set_cookie]).find("; Secure"), std::string::npos);
}

}  // namespace
}  // namespace incise::server::test
