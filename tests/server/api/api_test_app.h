#pragma once
// The REST router on a real SQLite file: a migrated database seeded with the demo data
// (server/demo_data.h), an AppState whose clock the test sets, and helpers that build requests the
// way an HttpSession hands them to handle_api_request(). The demo data is seeded once per suite
// and copied for each test, so argon2id hashing (~0.1 s per password) is paid once; sessions are
// created in the repository directly, without logging in.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "db/connection_pool.h"
#include "db/database.h"
#include "server/api/api_context.h"
#include "server/app_state.h"
#include "tests/support/temp_dir.h"

namespace incise::server::test {

using incise::test::TempDir;

inline constexpr std::int64_t kStart = 1894003200;  // 2030-01-07T08:00:00Z: the seed time
inline constexpr std::int64_t kDay = 86400;
inline constexpr const char* kHost = "incise.test:8080";
inline constexpr const char* kClient = "192.0.2.1";

// Who makes a request: nobody (no cookie) or one of the three demo logins.
enum class Who { nobody, trainee, instructor, admin };
inline constexpr Who kEveryone[] = {Who::nobody, Who::trainee, Who::instructor, Who::admin};
const char* name_of(Who who);

struct Call {
  Call(http::verb method, std::string target, std::optional<std::string> body = std::nullopt,
       std::string token = {})
      : method(method), target(std::move(target)), body(std::move(body)), token(std::move(token)) {}

  http::verb method;
  std::string target;
  std::optional<std::string> body;                // raw request body
  std::string token;                              // session cookie value; empty: no cookie
  std::string content_type = "application/json";  // sent when not empty and there is a body
  std::string origin;                             // Origin header; empty: none
  std::string client = kClient;                   // the remote address
  bool https = false;                             // reached over TLS
};

class ApiTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite();
  static void TearDownTestSuite();
  void SetUp() override;
  void TearDown() override;

  Response call(const Call& call);
  Response get(const std::string& target, const std::string& token);
  Response post(const std::string& target, const nlohmann::json& body, const std::string& token);
  Response put(const std::string& target, const nlohmann::json& body, const std::string& token);
  Response del(const std::string& target, const std::string& token);

  // A new session of `who` (empty for nobody), as if they had just logged in.
  std::string session_of(Who who);
  std::int64_t user_id(std::string_view username);
  // A trainee who cannot log in (no password hash): for ownership and visibility checks. Taught by
  // the demo instructor unless told otherwise.
  std::int64_t add_trainee(std::string_view username, bool taught_by_demo_instructor = true);
  std::int64_t demo_station_id();
  std::int64_t count(std::string_view table);

  void set_now(std::int64_t t) { now_ = t; }
  std::int64_t now() const { return now_; }
  db::Database& db() { return *db_; }
  AppState& app() { return *app_; }

  // The session lifetime is a setting; tests that move the clock may shorten it here.
  ServerConfig config_;

 private:
  static std::unique_ptr<TempDir> template_dir_;
  std::unique_ptr<TempDir> dir_;
  std::unique_ptr<db::Database> db_;  // the test's own connection, beside the server's pool
  std::unique_ptr<db::ConnectionPool> pool_;
  std::unique_ptr<AppState> app_;
  std::int64_t now_ = kStart;
};

// A JSON body, or null when the body is not JSON.
nlohmann::json json_of(const Response& response);
// Whether `response` is `status` with a JSON body {"error": non-empty string}, equal to `message`
// unless that is empty.
::testing::AssertionResult is_error(const Response& response, http::status status,
                                    std::string_view message = {});

}  // namespace incise::server::test
