#include "server_fixture.h"

#include <signal.h>

#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <stdexcept>

#include "db/database.h"
#include "db_snapshot.h"

namespace incise::server::test {

namespace {
// A fresh database `name` on the cluster INCISE_TEST_DATABASE names; returns its URL.
db::DatabaseUrl create_database(const db::DatabaseUrl& cluster, const std::string& name) {
  db::Database(cluster).exec("CREATE DATABASE " + name);
  // postgresql://user@host/DB?params: replace DB (the path after the authority).
  auto url = cluster;
  const auto path = url.target.find('/', url.target.find("://") + 3);
  const auto end = url.target.find('?', path);
  url.target.replace(path + 1, (end == std::string::npos ? url.target.size() : end) - path - 1,
                     name);
  return url;
}
}  // namespace

ServerProcess::ServerProcess(std::vector<std::string> extra_args,
                             const ServerProcess* same_database_as) {
  const auto web = dir_.path() / "web";
  std::filesystem::create_directories(web);
  std::ofstream(web / "index.html") << kIndexHtml;
  std::vector<std::string> command{INCISE_SERVER_BIN,
                                   "--port",
                                   "0",
                                   "--host",
                                   "127.0.0.1",
                                   "--data",
                                   (dir_.path() / "data").string(),
                                   "--demo",
                                   "--web",
                                   web.string()};
  database_ = db::DatabaseUrl::sqlite(dir_.path() / "data" / "incise.db");
  const char* server = std::getenv("INCISE_TEST_DATABASE");
  if (same_database_as) {
    database_ = same_database_as->database_;
    command.insert(command.end(), {"--database", database_.dialect == db::Dialect::sqlite
                                                     ? "sqlite:" + database_.target
                                                     : database_.target});
  } else if (server && *server) {
    cluster_ = db::DatabaseUrl::parse(server);
    static int count = 0;
    database_name_ = "incise_it" + std::to_string(::getpid()) + "_" + std::to_string(++count);
    database_ = create_database(cluster_, database_name_);
    command.insert(command.end(), {"--database", database_.target});
  }
  command.insert(command.end(), extra_args.begin(), extra_args.end());
  process_ = std::make_unique<ChildProcess>(command);
  const auto line = process_->wait_for_line(kListening, std::chrono::seconds(20));
  if (!line) {
    const auto status = process_->wait_for_exit(std::chrono::milliseconds(0));
    throw std::runtime_error(std::string("incise-server did not start listening within 20 s") +
                             (status ? " (exit status " + std::to_string(*status) + ")" : "") +
                             "; stdout: " + process_->stdout_text() +
                             "; stderr: " + process_->stderr_text());
  }
  port_ = static_cast<unsigned short>(std::stoi(line->substr(std::string_view(kListening).size())));
}

ServerProcess::~ServerProcess() {
  process_.reset();  // the server first: it holds connections to the database
  if (database_name_.empty()) return;
  try {
    db::Database(cluster_).exec("DROP DATABASE IF EXISTS " + database_name_ + " WITH (FORCE)");
  } catch (const std::exception& e) {
    ADD_FAILURE() << "cannot drop the test database: " << e.what();
  }
}

std::unique_ptr<HttpClient> ServerProcess::client() const {
  return std::make_unique<HttpClient>("127.0.0.1", port_);
}

std::unique_ptr<ServerProcess> ServerTest::server_;
std::string ServerTest::start_error_;
std::map<std::string, std::unique_ptr<HttpClient>> ServerTest::clients_;

void ServerTest::SetUpTestSuite() {
  // A write to a socket the server has closed must fail the write, not kill the test.
  signal(SIGPIPE, SIG_IGN);
  start_error_.clear();
  try {
    server_ = std::make_unique<ServerProcess>();
  } catch (const std::exception& e) {
    start_error_ = e.what();
  }
}

void ServerTest::TearDownTestSuite() {
  clients_.clear();
  server_.reset();  // kills the server if a test has not stopped it
}

void ServerTest::SetUp() {
  ASSERT_TRUE(server_) << start_error_;
}

void ServerTest::TearDown() {
  if (!server_) return;
  const auto log = server_->process().stderr_text();
  EXPECT_EQ(log.find("internal error"), std::string::npos) << log;
}

HttpClient& ServerTest::as(const Login& login) {
  auto& client = clients_[login.username];
  if (!client) {
    client = new_client();
    const auto response = client->login(login.username, login.password);
    EXPECT_EQ(response.status, 200) << login.username << ": " << response.error();
  }
  return *client;
}

std::string ServerTest::snapshot() {
  return snapshot_tables(server_->database());
}

std::int64_t ServerTest::db_int(const std::string& sql) {
  return query_int(server_->database(), sql);
}

::testing::AssertionResult is_error(const HttpResponse& response, int status,
                                    std::string_view message) {
  if (response.status != status) {
    return ::testing::AssertionFailure()
           << "status " << response.status << ", expected " << status << "; " << response.error();
  }
  if (response.content_type != "application/json") {
    return ::testing::AssertionFailure() << "Content-Type '" << response.content_type << "'";
  }
  const auto body = response.json();
  if (!body.is_object() || body.size() != 1 || !body.contains("error") ||
      !body["error"].is_string() || body["error"].get<std::string>().empty()) {
    return ::testing::AssertionFailure() << "not {\"error\": non-empty string}: " << response.body;
  }
  if (!message.empty() && body["error"].get<std::string>() != message) {
    return ::testing::AssertionFailure()
           << "error '" << body["error"].get<std::string>() << "', expected '" << message << "'";
  }
  return ::testing::AssertionSuccess();
}

std::int64_t quarter_hour_in_days(int days) {
  const std::int64_t now = std::time(nullptr);
  return (now / 900 + 1) * 900 + std::int64_t{days} * 86400;
}

std::string utc_text(std::int64_t unix_seconds) {
  const std::time_t t = unix_seconds;
  std::tm tm{};
  gmtime_r(&t, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

}  // namespace incise::server::test
