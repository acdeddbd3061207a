// Malformed, oversized, invalid and unauthorised requests against the real server: the exact
// status and message, and an unchanged database.
#include <gtest/gtest.h>

#include <string>

#include "server_fixture.h"

namespace incise::server::test {
namespace {

using Requests = ServerTest;

TEST_F(Requests, MalformedJsonIs400) {
  auto& admin = as(kAdmin);
  const auto before = snapshot();
  for (const char* body : {"{", "{\"name\": }", "not json", ""}) {
    const auto response = admin.request(http::verb::post, "/api/stations", body,
                                        {{"Content-Type", "application/json"}});
    EXPECT_TRUE(is_error(response, 400)) << body;
    EXPECT_EQ(response.error().rfind("malformed JSON", 0), 0u) << response.error();
  }
  EXPECT_EQ(snapshot(), before);
}

TEST_F(Requests, BodiesOver64KiBAre413AndTheServerCarriesOn) {
  auto client = new_client();
  const auto before = snapshot();
  const std::string padding(64 * 1024 + 1 - std::string(R"({"username":"","password":"x"})").size(),
                            'a');
  const std::string body = R"({"username":")" + padding + R"(","password":"x"})";
  ASSERT_EQ(body.size(), 64u * 1024 + 1);
  const auto response =
      client->request(http::verb::post, "/api/login", body, {{"Content-Type", "application/json"}});
  EXPECT_TRUE(is_error(response, 413, "request body exceeds 64 KiB"));
  EXPECT_FALSE(response.keep_alive);
  EXPECT_EQ(snapshot(), before);
  // The same client (on a new connection) and another one are served as before.
  EXPECT_EQ(client->get("/api/health").status, 200);
  EXPECT_EQ(as(kTrainee).get("/api/me").status, 200);
  // Exactly at the limit, the body is read and judged on its content.
  const std::string fits = R"({"username":")" + padding.substr(1) + R"(","password":"x"})";
  ASSERT_EQ(fits.size(), 64u * 1024);
  EXPECT_TRUE(is_error(
      client->request(http::verb::post, "/api/login", fits, {{"Content-Type", "application/json"}}),
      401, "wrong username or password"));
}

TEST_F(Requests, InvalidFieldsAre422) {
  auto& admin = as(kAdmin);
  const auto before = snapshot();
  EXPECT_TRUE(is_error(admin.post("/api/stations", {{"name", "Station 9"}, {"colour", "red"}}), 422,
                       "unknown field 'colour'"));
  EXPECT_TRUE(
      is_error(admin.post("/api/stations", {{"name", 9}}), 422, "field 'name' must be a string"));
  EXPECT_TRUE(
      is_error(admin.post("/api/stations", nlohmann::json::object()), 422, "missing field 'name'"));
  EXPECT_TRUE(is_error(admin.post("/api/stations", nlohmann::json::array()), 422,
                       "body must be a JSON object"));
  EXPECT_TRUE(is_error(admin.post("/api/bookings", {{"station_id", "1"},
                                                    {"starts_at", "2030-01-01T00:00:00Z"},
                                                    {"ends_at", "2030-01-01T01:00:00Z"}}),
                       422, "field 'station_id' must be an integer"));
  EXPECT_EQ(snapshot(), before);
}

TEST_F(Requests, WrongRoleIs403) {
  auto& trainee = as(kTrainee);
  const auto before = snapshot();
  EXPECT_TRUE(is_error(
      trainee.post("/api/users",
                   {{"username", "mallory"}, {"password", "kestrel-0942"}, {"role", "admin"}}),
      403, "this needs the role admin (you are trainee)"));
  EXPECT_TRUE(
      is_error(trainee.get("/api/users"), 403, "this needs the role admin (you are trainee)"));
  EXPECT_TRUE(is_error(as(kInstructor).post("/api/stations", {{"name", "Station 9"}}), 403,
                       "this needs the role admin (you are instructor)"));
  EXPECT_EQ(snapshot(), before);
}

TEST_F(Requests, NoLoginIs401) {
  auto client = new_client();
  const auto before = snapshot();
  for (const char* path : {"/api/me", "/api/bookings", "/api/stations", "/api/users"}) {
    EXPECT_TRUE(is_error(client->get(path), 401, "not logged in")) << path;
  }
  EXPECT_TRUE(
      is_error(client->post("/api/bookings", nlohmann::json::object()), 401, "not logged in"));
  EXPECT_EQ(snapshot(), before);
}

TEST_F(Requests, CsrfDefences) {
  auto& admin = as(kAdmin);
  const auto before = snapshot();
  const std::string body = R"({"name": "Station 9"})";
  EXPECT_TRUE(is_error(admin.request(http::verb::post, "/api/stations", body), 400,
                       "Content-Type must be application/json"));
  EXPECT_TRUE(is_error(
      admin.request(http::verb::post, "/api/stations", body, {{"Content-Type", "text/plain"}}), 400,
      "Content-Type must be application/json"));
  EXPECT_TRUE(is_error(
      admin.request(http::verb::post, "/api/stations", body,
                    {{"Content-Type", "application/json"}, {"Origin", "http://evil.example"}}),
      403, "cross-origin request refused"));
  EXPECT_EQ(snapshot(), before);
  const auto same =
      admin.request(http::verb::post, "/api/stations", body,
                    {{"Content-Type", "application/json"}, {"Origin", admin.origin()}});
  EXPECT_EQ(same.status, 201) << same.error();
}

TEST_F(Requests, UnknownEndpointsAndWrongMethods) {
  auto& admin = as(kAdmin);
  EXPECT_TRUE(is_error(admin.get("/api/nothing"), 404, "no such endpoint: GET /api/nothing"));
  EXPECT_TRUE(is_error(admin.del("/api/bookings/987654"), 404, "booking 987654 does not exist"));
  EXPECT_TRUE(is_error(admin.get("/api/login"), 405, "GET is not allowed on /api/login"));
  EXPECT_TRUE(is_error(
      admin.request(http::verb::put, "/api/stations", "{}", {{"Content-Type", "application/json"}}),
      405, "PUT is not allowed on /api/stations"));
}

}  // namespace
}  // namespace incise::server::test
