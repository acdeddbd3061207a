// Dispatch, access rules and CSRF defence of the REST API: server/api/router.h, on a real SQLite
// file (api_test_app.h).
#include "server/api/router.h"

#include <gtest/gtest.h>

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "api_test_app.h"
#include "db/bookings_repo.h"
#include "server/time_text.h"
#include "tests/support/hostile_json.h"

namespace incise::server::test {
namespace {

constexpr int kUnauthorized = 401;
constexpr int kForbidden = 403;

// One endpoint of docs/api.md with the status each caller gets, in the order of kEveryone:
// nobody, trainee, instructor, admin.
struct Access {
  http::verb method;
  std::string path;
  std::array<int, 4> status;
};

class Router : public ApiTest {
 protected:
  // A bookable slot that no other call of this test uses: 1 h, one day ahead, then onwards.
  nlohmann::json next_slot_body() {
    const std::int64_t start = now() + kDay + 2 * 3600 * slots_++;
    return {{"station_id", demo_station_id()},
            {"starts_at", format_utc(start)},
            {"ends_at", format_utc(start + 3600)}};
  }

  // A fresh active booking of the demo trainee; returns its id.
  std::int64_t trainee_booking() {
    const std::int64_t start = now() + 2 * kDay + 2 * 3600 * slots_++;
    return db::BookingsRepo(db())
        .create(demo_station_id(), user_id("trainee"), start, start + 3600, now())
        .id;
  }

  // The request body each endpoint needs to succeed (null: none).
  std::optional<std::string> body_for(const Access& a, Who who) {
    if (a.path == "/api/login") {
      return nlohmann::json{{"username", "trainee"}, {"password", "incise-trainee-demo"}}.dump();
    }
    if (a.path == "/api/logout") return "{}";
    if (a.method == http::verb::post && a.path == "/api/users") {
      return nlohmann::json{{"username", std::string("made-by-") + name_of(who)},
                            {"password", "long enough password"},
                            {"role", "trainee"}}
          .dump();
    }
    if (a.method == http::verb::post && a.path == "/api/stations") {
      return nlohmann::json{{"name", std::string("Station of ") + name_of(who)}}.dump();
    }
    if (a.method == http::verb::post && a.path == "/api/bookings") return next_slot_body().dump();
    return std::nullopt;
  }

  int slots_ = 0;
};

// Every endpoint of docs/api.md, for every role and for no login.
TEST_F(Router, AccessTable) {
  const std::vector<Access> table = {
      {http::verb::get, "/api/health", {200, 200, 200, 200}},
      {http::verb::get, "/api/ready", {200, 200, 200, 200}},
      {http::verb::post, "/api/login", {200, 200, 200, 200}},
      {http::verb::post, "/api/logout", {204, 204, 204, 204}},
      {http::verb::get, "/api/me", {401, 200, 200, 200}},
      {http::verb::get, "/api/users", {401, 403, 403, 200}},
      {http::verb::post, "/api/users", {401, 403, 403, 201}},
      {http::verb::get, "/api/stations", {401, 200, 200, 200}},
      {http::verb::post, "/api/stations", {401, 403, 403, 201}},
      {http::verb::get, "/api/bookings", {401, 200, 200, 200}},
      {http::verb::post, "/api/bookings", {401, 201, 201, 201}},
      // The trainee's own booking: the owner or an admin may cancel it.
      {http::verb::delete_, "/api/bookings/{id}", {401, 204, 403, 204}},
      {http::verb::get, "/api/sessions", {401, 200, 200, 200}},
      {http::verb::get, "/api/recordings", {401, 200, 200, 200}},
      {http::verb::get, "/api/scores", {401, 200, 200, 200}},
      {http::verb::get, "/api/curricula", {401, 200, 200, 200}},
  };
  for (const auto& a : table) {
    for (std::size_t w = 0; w < std::size(kEveryone); ++w) {
      const Who who = kEveryone[w];
      std::string target = a.path;
      if (const auto at = target.find("{id}"); at != std::string::npos) {
        target.replace(at, 4, std::to_string(trainee_booking()));
      }
      SCOPED_TRACE(std::string(http::to_string(a.method)) + " " + target + " as " + name_of(who));
      const auto response = call({a.method, target, body_for(a, who), session_of(who)});
      const int expected = a.status[w];
      EXPECT_EQ(response.result_int(), expected) << response.body();
      if (expected == kUnauthorized) {
        EXPECT_TRUE(is_error(response, http::status::unauthorized, "not logged in"));
      } else if (expected == kForbidden && a.method == http::verb::delete_) {
        EXPECT_TRUE(
            is_error(response, http::status::forbidden, "you can cancel only your own bookings"));
      } else if (expected == kForbidden) {
        EXPECT_TRUE(
            is_error(response, http::status::forbidden,
                     std::string("this needs the role admin (you are ") + name_of(who) + ")"));
      } else if (expected == 204) {
        EXPECT_EQ(response.body(), "");
      } else {
        EXPECT_EQ(response[http::field::content_type], "application/json");
        EXPECT_FALSE(json_of(response).is_discarded()) << response.body();
      }
    }
  }
}

TEST_F(Router, RefusedWritesChangeNothing) {
  const auto users = count("users");
  const auto stations = count("stations");
  for (const Who who : {Who::nobody, Who::trainee, Who::instructor}) {
    SCOPED_TRACE(name_of(who));
    const auto token = session_of(who);
    post("/api/users",
         {{"username", "sneaky"}, {"password", "long enough password"}, {"role", "admin"}}, token);
    post("/api/stations", {{"name", "Sneaky station"}}, token);
    EXPECT_EQ(count("users"), users);
    EXPECT_EQ(count("stations"), stations);
  }
}

TEST_F(Router, UnknownEndpointsAre404) {
  const auto token = session_of(Who::admin);
  EXPECT_TRUE(is_error(get("/api/nothing", token), http::status::not_found,
                       "no such endpoint: GET /api/nothing"));
  EXPECT_TRUE(is_error(get("/api", token), http::status::not_found, "no such endpoint: GET /api"));
  EXPECT_TRUE(is_error(get("/api/users/", token), http::status::not_found));
  EXPECT_TRUE(is_error(get("/api/health/extra", ""), http::status::not_found));
  EXPECT_TRUE(is_error(del("/api/bookings/abc", token), http::status::not_found));
  EXPECT_TRUE(is_error(del("/api/bookings/0", token), http::status::not_found));
  EXPECT_TRUE(is_error(del("/api/bookings/-3", token), http::status::not_found));
  EXPECT_TRUE(is_error(del("/api/bookings/99999", token), http::status::not_found,
                       "booking 99999 does not exist"));
  // Unknown even for nobody: the path is checked before the login.
  EXPECT_TRUE(is_error(post("/api/nothing", {}, ""), http::status::not_found,
                       "no such endpoint: POST /api/nothing"));
}

TEST_F(Router, KnownPathsWithAWrongMethodAre405) {
  const auto token = session_of(Who::admin);
  const std::vector<std::pair<http::verb, std::string>> cases = {
      {http::verb::get, "/api/login"},      {http::verb::get, "/api/logout"},
      {http::verb::post, "/api/me"},        {http::verb::delete_, "/api/users"},
      {http::verb::put, "/api/stations"},   {http::verb::patch, "/api/bookings"},
      {http::verb::get, "/api/bookings/1"}, {http::verb::post, "/api/health"},
      {http::verb::post, "/api/scores"},    {http::verb::delete_, "/api/curricula"},
  };
  for (const auto& [method, path] : cases) {
    const auto response = call({method, path, std::string("{}"), token});
    EXPECT_TRUE(is_error(response, http::status::method_not_allowed,
                         std::string(http::to_string(method)) + " is not allowed on " + path))
        << path;
  }
}

// The server never grants a CORS preflight, so a cross-site page cannot send JSON with the cookie.
TEST_F(Router, NoCorsPreflight) {
  Call preflight{http::verb::options, "/api/bookings"};
  preflight.origin = "http://evil.example";
  const auto response = call(preflight);
  EXPECT_TRUE(is_error(response, http::status::method_not_allowed,
                       "OPTIONS is not allowed on /api/bookings"));
  EXPECT_EQ(response["Access-Control-Allow-Origin"], "");
  EXPECT_EQ(response["Access-Control-Allow-Credentials"], "");
}

TEST_F(Router, QueryStringsAreIgnoredForRouting) {
  const auto response = get("/api/me?fields=all", session_of(Who::trainee));
  EXPECT_EQ(response.result(), http::status::ok);
  EXPECT_EQ(json_of(response)["username"], "trainee");
}

TEST_F(Router, StateChangingRequestsMustBeJson) {
  const auto token = session_of(Who::trainee);
  const auto bookings = count("bookings");
  for (const char* type :
       {"", "text/plain", "application/x-www-form-urlencoded", "multipart/form-data; boundary=x",
        "application/jsonx", "application/json-patch+json", "application/jsonp; charset=utf-8"}) {
    Call c{http::verb::post, "/api/bookings", next_slot_body().dump(), token};
    c.content_type = type;
    EXPECT_TRUE(
        is_error(call(c), http::status::bad_request, "Content-Type must be application/json"))
        << "'" << type << "'";
  }
  EXPECT_EQ(count("bookings"), bookings);
  Call c{http::verb::post, "/api/bookings", next_slot_body().dump(), token};
  c.content_type = "Application/JSON ; charset=utf-8";  // the media type is case-insensitive
  EXPECT_EQ(call(c).result(), http::status::created);
  // Logging in is state-changing too.
  Call login{http::verb::post, "/api/login", R"({"username": "a", "password": "b"})"};
  login.content_type = "";
  EXPECT_TRUE(
      is_error(call(login), http::status::bad_request, "Content-Type must be application/json"));
}

TEST_F(Router, ForeignOriginsAreRefused) {
  const auto token = session_of(Who::trainee);
  const auto bookings = count("bookings");
  // Another scheme on this very host is another origin too (ftp://, a data: or file page).
  const std::string host = kHost;
  for (const std::string& origin :
       {std::string("http://evil.example"), std::string("https://evil.example:8080"),
        std::string("http://incise.test:8081"), std::string("null"),
        std::string("http://incise.test"), "ftp://" + host, "file://" + host, host, "//" + host}) {
    Call c{http::verb::post, "/api/bookings", next_slot_body().dump(), token};
    c.origin = origin;
    EXPECT_TRUE(is_error(call(c), http::status::forbidden, "cross-origin request refused"))
        << origin;
  }
  EXPECT_EQ(count("bookings"), bookings);

  const auto booking = trainee_booking();
  Call cancel{http::verb::delete_, "/api/bookings/" + std::to_string(booking), std::nullopt, token};
  cancel.origin = "http://evil.example";
  EXPECT_TRUE(is_error(call(cancel), http::status::forbidden, "cross-origin request refused"));
  EXPECT_EQ(db::BookingsRepo(db()).find(booking)->status, "active");
}

TEST_F(Router, SameOriginIsAccepted) {
  const auto token = session_of(Who::trainee);
  Call c{http::verb::post, "/api/bookings", next_slot_body().dump(), token};
  c.origin = std::string("http://") + kHost;
  EXPECT_EQ(call(c).result(), http::status::created);
  Call cancel{http::verb::delete_, "/api/bookings/" + std::to_string(trainee_booking()),
              std::nullopt, token};
  cancel.origin = std::string("http://") + kHost;
  EXPECT_EQ(call(cancel).result(), http::status::no_content);
  // Behind a TLS proxy the page is https on the same host.
  Call tls{http::verb::post, "/api/logout", "{}", token};
  tls.origin = std::string("https://") + kHost;
  EXPECT_EQ(call(tls).result(), http::status::no_content);
}

TEST_F(Router, ReadsNeedNoJsonContentType) {
  // GET carries no body; a cross-site GET cannot change anything.
  Call c{http::verb::get, "/api/stations", std::nullopt, session_of(Who::trainee)};
  c.origin = "http://evil.example";
  EXPECT_EQ(call(c).result(), http::status::ok);
}

TEST_F(Router, ResponsesAreNotCached) {
  const auto token = session_of(Who::trainee);
  EXPECT_EQ(get("/api/me", token)[http::field::cache_control], "no-store");
  EXPECT_EQ(get("/api/me", "")[http::field::cache_control], "no-store");
}

TEST_F(Router, MalformedJsonIs400) {
  const auto token = session_of(Who::admin);
  for (const char* body : {"", "{", "{\"name\": }", "[1, 2", "nul", "{'a': 1}"}) {
    const auto response = call({http::verb::post, "/api/stations", body, token});
    EXPECT_TRUE(is_error(response, http::status::bad_request)) << body;
    EXPECT_EQ(json_of(response).value("error", "").rfind("malformed JSON: parse error", 0), 0u)
        << response.body();
  }
}

// Bytes a client sent never break the error path: an echoed path that is not UTF-8 comes back as
// valid JSON with U+FFFD in its place (an HttpSession refuses such targets before routing; the
// router must still be safe on its own).
TEST_F(Router, InvalidUtf8InThePathIsEchoedAsValidJson) {
  for (const std::string path :
       {"/api/\xff", "/api/\xc0\xaf", "/api/\xed\xa0\x80", "/api/health/\xf4\x90\x80\x80"}) {
    Response response;
    ASSERT_NO_THROW(response = get(path, "")) << path;
    EXPECT_TRUE(is_error(response, http::status::not_found)) << response.body();
    const auto error = json_of(response).value("error", "");
    EXPECT_TRUE(error.starts_with("no such endpoint: GET /api/")) << error;
    EXPECT_NE(error.find("\xEF\xBF\xBD"), std::string::npos) << error;
  }
  // json_error itself, with a message of any bytes and any length.
  const auto response = json_error(http::status::bad_request, std::string(10000, '\xff'), 11, true);
  const auto error = json_of(response).value("error", "");
  EXPECT_LE(error.size(), 512u);
  EXPECT_TRUE(incise::test::is_utf8(error));
}

// Every endpoint that reads a body answers a hostile value in it with 400 (not JSON: invalid
// UTF-8, overlong or surrogate encodings, lone surrogate escapes) or 422 (a number beyond a
// double's range), never 500, and stores nothing.
TEST_F(Router, HostileValuesInBodiesAre400Or422) {
  const auto station = std::to_string(demo_station_id());
  const auto trainee = std::to_string(user_id("trainee"));
  struct Endpoint {
    http::verb method;
    std::string path;
    Who who;
    const char* body;
  };
  const Endpoint endpoints[] = {
      {http::verb::post, "/api/login", Who::nobody, R"({"username": @, "password": "x"})"},
      {http::verb::post, "/api/users", Who::admin, R"({"username": "u", "password": @})"},
      {http::verb::put, "/api/users/" + trainee + "/instructors", Who::admin,
       R"({"instructor_ids": [@]})"},
      {http::verb::post, "/api/stations", Who::admin, R"({"name": @})"},
      {http::verb::put, "/api/stations/" + station + "/calibration", Who::admin,
       R"({"devices": [{"scale": @}]})"},
      {http::verb::post, "/api/bookings", Who::trainee,
       R"({"station_id": @, "starts_at": "x", "ends_at": "y"})"},
      {http::verb::post, "/api/sessions", Who::trainee, R"({"station_id": 1, "task": @})"},
      {http::verb::post, "/api/curricula", Who::admin, R"({"name": @, "modules": []})"},
  };
  const auto tables = {"users", "stations", "bookings", "sessions", "curricula", "audit_log"};
  std::vector<std::int64_t> before;
  for (const auto* table : tables)
    before.push_back(count(table));
  for (const auto& endpoint : endpoints) {
    const auto token = session_of(endpoint.who);
    for (const auto& value : incise::test::hostile_values()) {
      const auto body = incise::test::with_value(endpoint.body, value.token);
      Response response;
      ASSERT_NO_THROW(response = call({endpoint.method, endpoint.path, body, token}));
      const auto status =
          value.number ? http::status::unprocessable_entity : http::status::bad_request;
      EXPECT_TRUE(is_error(response, status)) << endpoint.path << ", " << value.what;
      const auto error = json_of(response).value("error", "");
      EXPECT_TRUE(error.starts_with(value.number ? "number out of range: " : "malformed JSON: "))
          << error;
    }
  }
  std::size_t i = 0;
  for (const auto* table : tables)
    EXPECT_EQ(count(table), before[i++]) << table;
  // The integer fields refuse what does not fit a rowid instead of wrapping it to a negative.
  const auto admin = session_of(Who::admin);
  EXPECT_TRUE(is_error(call({http::verb::post, "/api/bookings",
                             R"({"station_id": 18446744073709551615, "starts_at": "x",
                                 "ends_at": "y"})",
                             session_of(Who::trainee)}),
                       http::status::unprocessable_entity,
                       "field 'station_id' is out of range (at most 2^63 - 1)"));
  // Nesting a body deeper than the parser's limit is refused before it is parsed.
  EXPECT_TRUE(is_error(
      call({http::verb::post, "/api/stations",
            R"({"name": "n", "x": )" + std::string(1000, '[') + std::string(1000, ']') + "}",
            admin}),
      http::status::bad_request, "malformed JSON: nested deeper than 64 levels"));
}

}  // namespace
}  // namespace incise::server::test
