#include "api_test_app.h"

#include "db/auth_sessions_repo.h"
#include "db/migrations.h"
#include "db/statement.h"
#include "db/stations_repo.h"
#include "db/users_repo.h"
#include "server/api/router.h"
#include "server/demo_data.h"

namespace incise::server::test {

namespace {
constexpr const char* kDatabaseFile = "incise.db";
}  // namespace

std::unique_ptr<TempDir> ApiTest::template_dir_;

const char* name_of(Who who) {
  switch (who) {
    case Who::nobody:
      return "nobody";
    case Who::trainee:
      return "trainee";
    case Who::instructor:
      return "instructor";
    case Who::admin:
      return "admin";
  }
  return "?";
}

void ApiTest::SetUpTestSuite() {
  template_dir_ = std::make_unique<TempDir>("incise-api-template");
  // Closing the only connection checkpoints the WAL, so the one file holds everything.
  db::Database seed(template_dir_->path() / kDatabaseFile);
  db::apply_migrations(seed);
  ASSERT_TRUE(seed_demo_data(seed, kStart));
}

void ApiTest::TearDownTestSuite() {
  template_dir_.reset();
}

void ApiTest::SetUp() {
  ASSERT_TRUE(template_dir_);
  dir_ = std::make_unique<TempDir>("incise-api");
  std::filesystem::copy_file(template_dir_->path() / kDatabaseFile, dir_->path() / kDatabaseFile);
  db_ = std::make_unique<db::Database>(dir_->path() / kDatabaseFile);
  pool_ = std::make_unique<db::ConnectionPool>(
      db::DatabaseUrl::sqlite(dir_->path() / kDatabaseFile), 4);
  app_ = std::make_unique<AppState>(*pool_, config_);
  app_->set_clock([this] { return now_; });
}

void ApiTest::TearDown() {
  app_.reset();
  pool_.reset();
  db_.reset();
  dir_.reset();
}

Response ApiTest::call(const Call& c) {
  Request request{c.method, c.target, 11};
  request.set(http::field::host, kHost);
  if (!c.token.empty()) {
    request.set(http::field::cookie, "theme=dark; " + std::string(kSessionCookie) + "=" + c.token);
  }
  if (!c.origin.empty()) request.set(http::field::origin, c.origin);
  if (c.body) {
    if (!c.content_type.empty()) request.set(http::field::content_type, c.content_type);
    request.body() = *c.body;
  }
  request.prepare_payload();
  return handle_api_request(request, *app_, {c.client, c.https});
}

Response ApiTest::get(const std::string& target, const std::string& token) {
  return call({http::verb::get, target, std::nullopt, token});
}

Response ApiTest::post(const std::string& target, const nlohmann::json& body,
                       const std::string& token) {
  return call({http::verb::post, target, body.dump(), token});
}

Response ApiTest::put(const std::string& target, const nlohmann::json& body,
                      const std::string& token) {
  return call({http::verb::put, target, body.dump(), token});
}

Response ApiTest::del(const std::string& target, const std::string& token) {
  return call({http::verb::delete_, target, std::nullopt, token});
}

std::string ApiTest::session_of(Who who) {
  if (who == Who::nobody) return "";
  return db::AuthSessionsRepo(*db_).create(user_id(name_of(who)), now_,
                                           app_->config().session_ttl_s);
}

std::int64_t ApiTest::user_id(std::string_view username) {
  auto q = db_->prepare("SELECT id FROM users WHERE username = ?");
  q.bind(1, username);
  if (!q.step()) throw std::runtime_error("no user " + std::string(username));
  return q.int64(0);
}

std::int64_t ApiTest::add_trainee(std::string_view username, bool taught_by_demo_instructor) {
  const std::int64_t id =
      db_->prepare(
             "INSERT INTO users (username, display_name, role, password_hash, created_at) VALUES "
             "(?, ?, 'trainee', 'not-a-hash', ?) RETURNING id")
          .bind(1, username)
          .bind(2, username)
          .bind(3, now_)
          .insert();
  if (taught_by_demo_instructor) {
    db::UsersRepo(*db_).set_instructors(id, {user_id("instructor")}, now_);
  }
  return id;
}

std::int64_t ApiTest::demo_station_id() {
  const auto station = db::StationsRepo(*db_).find_by_token(kDemoStationToken);
  if (!station) throw std::runtime_error("no demo station");
  return station->id;
}

std::int64_t ApiTest::count(std::string_view table) {
  auto q = db_->prepare("SELECT COUNT(*) FROM " + std::string(table));
  q.step();
  return q.int64(0);
}

nlohmann::json json_of(const Response& response) {
  return nlohmann::json::parse(response.body(), nullptr, false);
}

::testing::AssertionResult is_error(const Response& response, http::status status,
                                    std::string_view message) {
  if (response.result() != status) {
    return ::testing::AssertionFailure()
           << "status " << response.result_int() << ", expected " << static_cast<int>(status)
           << "; body " << response.body();
  }
  if (response[http::field::content_type] != "application/json") {
    return ::testing::AssertionFailure()
           << "Content-Type '" << response[http::field::content_type] << "'";
  }
  const auto body = json_of(response);
  if (!body.is_object() || body.size() != 1 || !body.contains("error") ||
      !body["error"].is_string() || body["error"].get<std::string>().empty()) {
    return ::testing::AssertionFailure()
           << "not {\"error\": non-empty string}: " << response.body();
  }
  if (!message.empty() && body["error"].get<std::string>() != message) {
    return ::testing::AssertionFailure()
           << "error '" << body["error"].get<std::string>() << "', expected '" << message << "'";
  }
  return ::testing::AssertionSuccess();
}

}  // namespace incise::server::test
