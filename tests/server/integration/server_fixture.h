#pragma once
// The real incise-server for integration tests: started with --demo on a fresh data directory
// (and, when INCISE_TEST_DATABASE names a PostgreSQL cluster as in the pg/ suites, a fresh
// database there, given with --database) and a tiny web root, one server per test suite, plus
// logged-in clients for the demo logins (logged in once per suite: argon2id costs ~0.1 s per
// login).
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "db/database_url.h"
#include "tests/support/child_process.h"
#include "tests/support/http_client.h"
#include "tests/support/temp_dir.h"

namespace incise::server::test {

using incise::test::ChildProcess;
using incise::test::TempDir;

struct Login {
  const char* username;
  const char* password;
};
inline constexpr Login kAdmin{"admin", "incise-admin-demo"};
inline constexpr Login kInstructor{"instructor", "incise-instructor-demo"};
inline constexpr Login kTrainee{"trainee", "incise-trainee-demo"};
// The demo trainee who has mastered the palpation tasks, for whom the stations' tasks are open.
inline constexpr Login kResident{"resident", "incise-resident-demo"};
inline constexpr const char* kStationToken = "incise-demo-station-token";
inline constexpr const char* kIndexHtml = "<!doctype html><title>Incise test dashboard</title>\n";
inline constexpr const char* kListening = "incise-server: listening on http://127.0.0.1:";

class ServerProcess {
 public:
  // Throws std::runtime_error, with the server's stderr, when it is not listening within 20 s.
  // `extra_args` go on the command line; with `same_database_as`, this server shares that one's
  // database (another node of the same platform) instead of getting a fresh one.
  explicit ServerProcess(std::vector<std::string> extra_args = {},
                         const ServerProcess* same_database_as = nullptr);
  ~ServerProcess();
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  unsigned short port() const { return port_; }
  // Where the server keeps its data: data/incise.db, or its own PostgreSQL database.
  const db::DatabaseUrl& database() const { return database_; }
  ChildProcess& process() { return *process_; }
  std::unique_ptr<HttpClient> client() const;

 private:
  TempDir dir_{"incise-server-it"};
  db::DatabaseUrl cluster_;  // PostgreSQL only: the server database_name_ was created on
  std::string database_name_;
  db::DatabaseUrl database_;
  std::unique_ptr<ChildProcess> process_;
  unsigned short port_ = 0;
};

class ServerTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite();
  static void TearDownTestSuite();
  void SetUp() override;
  void TearDown() override;

  static ServerProcess& server() { return *server_; }
  // A client logged in as `login`, the same one for the whole suite.
  static HttpClient& as(const Login& login);
  static std::unique_ptr<HttpClient> new_client() { return server_->client(); }

  static std::string snapshot();
  static std::int64_t db_int(const std::string& sql);

 private:
  static std::unique_ptr<ServerProcess> server_;
  static std::string start_error_;
  static std::map<std::string, std::unique_ptr<HttpClient>> clients_;
};

// Whether `response` is `status` with a JSON body {"error": non-empty string}, equal to
// `message` unless that is empty.
::testing::AssertionResult is_error(const HttpResponse& response, int status,
                                    std::string_view message = {});

// A quarter hour `days` days from now (server time is real time here), and its API text.
std::int64_t quarter_hour_in_days(int days);
std::string utc_text(std::int64_t unix_seconds);

}  // namespace incise::server::test
