// Whole HTTP requests, bytes as they come off a socket, through the server's request path
// (server/http/http_session.h): Beast's parser with the server's limits, refuse_request, then the
// REST router and its handlers (every body family) or the static files, on a real SQLite
// database with the demo data. The first byte chooses whose login cookie is added (none, a
// trainee's, an instructor's, an admin's), so that the fuzzer reaches the handlers behind the
// login. The contract: no exception escapes, no answer is a 500 (an unexpected error), and every
// API answer is JSON (or the CSV export) in valid UTF-8.
#include <boost/beast/http.hpp>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include <unistd.h>
#include <nlohmann/json.hpp>

#include "db/auth_sessions_repo.h"
#include "db/database.h"
#include "db/migrations.h"
#include "db/users_repo.h"
#include "fuzz/fuzz_target.h"
#include "server/app_state.h"
#include "server/demo_data.h"
#include "server/http/http_session.h"
#include "server/wire_text.h"

using namespace incise;
namespace http = boost::beast::http;

namespace {

struct World {
  std::filesystem::path dir;
  std::unique_ptr<db::Database> database;
  std::unique_ptr<db::ConnectionPool> pool;
  std::shared_ptr<server::AppState> app;
  std::string cookies[4];  // none, trainee, instructor, admin
};

World& world() {
  static World* w = [] {
    auto* w = new World;
    w->dir =
        std::filesystem::temp_directory_path() / ("incise-fuzz-http-" + std::to_string(getpid()));
    std::filesystem::remove_all(w->dir);
    std::filesystem::create_directories(w->dir);
    w->database = std::make_unique<db::Database>(w->dir / "incise.db");
    db::apply_migrations(*w->database);
    server::ServerConfig config;
    config.web_root = w->dir / "web";
    config.database = db::DatabaseUrl::sqlite(w->dir / "incise.db");
    std::filesystem::create_directories(config.web_root);
    std::ofstream(config.web_root / "index.html") << "<!doctype html><title>Incise</title>";
    w->pool = std::make_unique<db::ConnectionPool>(config.database, 2);
    w->app = std::make_shared<server::AppState>(*w->pool, config);
    server::seed_demo_data(*w->database, w->app->now());
    const char* names[] = {"trainee", "instructor", "admin"};
    for (int i = 0; i < 3; ++i) {
      const auto user = db::UsersRepo(*w->database).find_by_username(names[i]);
      const auto token =
          db::AuthSessionsRepo(*w->database).create(user->id, w->app->now(), 1 << 30);
      w->cookies[i + 1] = std::string(server::kSessionCookie) + "=" + token;
    }
    return w;
  }();
  return *w;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  auto& w = world();
  http::request_parser<http::string_body> parser;
  parser.header_limit(16 * 1024);
  parser.body_limit(w.app->config().api_body_limit);
  parser.eager(true);
  boost::beast::error_code ec;
  parser.put(boost::asio::buffer(data + 1, size - 1), ec);
  if (ec || !parser.is_done()) return 0;  // the session answers 400 or waits for more
  auto request = parser.release();
  if (const auto& cookie = w.cookies[data[0] & 3]; !cookie.empty()) {
    request.set(http::field::cookie, cookie);
  }
  // The password-checking requests run the same router on another thread; argon2 would only
  // slow the fuzzer down here.
  if (server::checks_password(request)) return 0;
  if (server::refuse_request(request)) return 0;
  const auto response = server::answer_request(request, *w.app, {"192.0.2.1"});
  fuzz_check(response.result() != http::status::internal_server_error);
  if (server::is_api_target(request.target())) {
    fuzz_check(server::is_valid_utf8(response.body()));
    const bool csv = response[http::field::content_type].starts_with("text/csv");
    if (!csv && !response.body().empty()) {
      fuzz_check(!nlohmann::json::parse(response.body(), nullptr, false).is_discarded());
    }
  }
  return 0;
}
