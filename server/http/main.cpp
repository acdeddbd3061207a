// incise-server: wires the database, the REST API, the dashboard and the agent link to one port.
#include <unistd.h>
#include <algorithm>
#include <boost/asio.hpp>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <thread>
#include <vector>

#include "db/calibration_repo.h"
#include "db/migrations.h"
#include "db/nodes_repo.h"
#include "server/app_state.h"
#include "server/demo_data.h"
#include "server/first_admin.h"
#include "server/http/listener.h"
#include "server/live/render_pool.h"
#include "server/node_heartbeat.h"
#include "server/server_options.h"
#include "server/wire_text.h"
#include "transport/tls_contexts.h"

namespace net = boost::asio;
using namespace incise;

namespace {
// Where the other nodes reach this one (server_options.h, --node-address); INCISE_NODE_ADDRESS
// was checked at start-up.
std::string this_node_address(const server::ServerOptions& options, unsigned short port) {
  if (!options.node_address.empty()) return options.node_address;
  if (const char* from_environment = std::getenv("INCISE_NODE_ADDRESS");
      from_environment && *from_environment) {
    return from_environment;
  }
  std::string host = options.host;
  if (host == "0.0.0.0" || host == "::") {
    char name[256] = {};
    host = gethostname(name, sizeof name - 1) == 0 ? name : "localhost";
  } else if (host.find(':') != std::string::npos) {
    host = "[" + host + "]";
  }
  return host + ":" + std::to_string(port);
}
}  // namespace

int main(int argc, char** argv) {
  const auto parsed = server::parse_server_options(std::vector<std::string>(argv + 1, argv + argc));
  if (!parsed.options) {
    std::cerr << "incise-server: " << parsed.error << "\n" << server::kServerUsage;
    return 2;
  }
  const auto& options = *parsed.options;
  if (options.help) {
    std::cout << server::kServerUsage;
    return 0;
  }

  // This node's name among the servers sharing the database: its sessions are its own.
  std::string node_id = options.node_id;
  if (const char* from_environment = std::getenv("INCISE_NODE_ID");
      node_id.empty() && from_environment && *from_environment) {
    node_id = from_environment;
  }
  if (node_id.empty()) {
    char host[256] = {};
    node_id = gethostname(host, sizeof host - 1) == 0 && server::is_node_id(host) ? host : "local";
  }
  if (!server::is_node_id(node_id)) {
    std::cerr << "incise-server: INCISE_NODE_ID must be 1-64 characters of a-z, A-Z, 0-9, '.', "
                 "'_' or '-'\n";
    return 2;
  }

  if (const char* address = std::getenv("INCISE_NODE_ADDRESS");
      options.node_address.empty() && address && *address && !server::is_node_address(address)) {
    std::cerr << "incise-server: INCISE_NODE_ADDRESS must be HOST:PORT\n";
    return 2;
  }

  db::DatabaseUrl database_url;
  try {
    const char* from_environment = std::getenv("INCISE_DATABASE_URL");
    if (!options.database.empty()) {
      database_url = db::DatabaseUrl::parse(options.database);
    } else if (from_environment && *from_environment) {
      database_url = db::DatabaseUrl::parse(from_environment);
    } else {
      std::filesystem::create_directories(options.data_dir);
      database_url = db::DatabaseUrl::sqlite(options.data_dir / "incise.db");
    }
    std::cerr << "incise-server: database " << database_url.redacted() << ", node " << node_id
              << "\n";
    const auto database = std::make_unique<db::Database>(database_url);
    const int applied = db::apply_migrations(*database);
    if (applied > 0) std::cerr << "incise-server: applied " << applied << " migration(s)\n";
    // A crash leaves this node's sessions running and recordings open. The sessions are aborted;
    // the recordings keep every committed chunk and are closed as they are. Other nodes' sessions
    // are theirs: a dead node's are ended by the heartbeat sweep (server/node_heartbeat.h).
    const auto now = std::chrono::duration_cast<std::chrono::seconds>(
                         std::chrono::system_clock::now().time_since_epoch())
                         .count();
    db::NodesRepo nodes(*database);
    const auto ended = nodes.end_sessions_of(node_id, now, true);
    for (const auto id : ended.sessions) {
      std::cerr << "incise-server: session " << id
                << " was running when this node stopped; marked aborted\n";
    }
    for (const auto id : ended.recordings)
      std::cerr << "incise-server: closed recording " << id << " left open by a crash\n";
    if (const int failed = db::CalibrationJobsRepo(*database).fail_unfinished(
            node_id, "the server stopped while it ran", now)) {
      std::cerr << "incise-server: " << failed << " calibration job(s) ended by the stop\n";
    }
    nodes.start(node_id, "", now);
  } catch (const std::exception& e) {
    std::cerr << "incise-server: " << e.what() << "\n";
    return 1;
  }

  // Before any session exists: the pool starts with its first picture.
  if (options.render_threads > 0)
    server::live::RenderPool::configure_shared(options.render_threads);

  server::ServerConfig config;
  config.web_root = options.web_root;
  config.database = database_url;
  config.node_id = node_id;
  config.node_timeout_s = options.node_timeout_s;
  config.demo = options.demo;
  config.secure_cookies = options.secure_cookies;
  config.trusted_proxy = options.trusted_proxy;
  // A connection for every thread that may run a request at once (the I/O threads, the password
  // workers and the long reads: half the cores each, server/worker_pool.h), and a few more for
  // the heartbeat and agents' lookups; live sessions open their own.
  const std::size_t workers = std::max(1u, std::thread::hardware_concurrency() / 2);
  db::ConnectionPool pool(database_url,
                          static_cast<std::size_t>(options.threads) + 2 * workers + 6);
  auto app = std::make_shared<server::AppState>(pool, config);
  if (options.demo) {
    try {
      if (server::seed_demo_data(*pool.acquire(), app->now())) {
        std::cerr << "incise-server: created demo data\n";
      }
      // Public, so for a demo only: a server started without --demo refuses them.
      std::cerr << "incise-server: demo mode: the demo stations' public tokens are accepted ("
                << server::kDemoStationToken << ", " << server::kDemoSurgicalStationToken << ", "
                << server::kDemoArthroscopyStationToken << ")\n";
    } catch (const std::exception& e) {
      std::cerr << "incise-server: demo data: " << e.what() << "\n";
      return 1;
    }
  }
  if (const char* password = std::getenv("INCISE_ADMIN_PASSWORD"); password && *password) {
    try {
      const auto first = server::create_first_admin(*pool.acquire(), password, app->now());
      if (!first.problem.empty()) {
        std::cerr << "incise-server: " << first.problem << "\n";
        return 2;
      }
      if (first.created) {
        std::cerr << "incise-server: created the first admin, \"admin\", with the password of "
                     "INCISE_ADMIN_PASSWORD; they choose another at the first login\n";
      }
    } catch (const std::exception& e) {
      std::cerr << "incise-server: first admin: " << e.what() << "\n";
      return 1;
    }
  }
  if (!std::filesystem::exists(options.web_root / "index.html")) {
    std::cerr << "incise-server: warning: no dashboard at " << options.web_root.string()
              << " (the API still works)\n";
  }

  std::shared_ptr<net::ssl::context> tls;
  if (!options.tls_cert.empty()) {
    try {
      tls = transport::make_server_tls(options.tls_cert.string(), options.tls_key.string());
    } catch (const std::exception& e) {
      std::cerr << "incise-server: " << server::valid_utf8(e.what()) << "\n";
      return 1;
    }
  }

  net::io_context ioc(options.threads);
  std::shared_ptr<server::Listener> listener;
  try {
    const net::ip::tcp::endpoint endpoint(net::ip::make_address(options.host), options.port);
    listener = std::make_shared<server::Listener>(ioc, endpoint, app, tls);
  } catch (const std::exception& e) {
    std::cerr << "incise-server: cannot listen on " << options.host << ":" << options.port << ": "
              << e.what() << "\n";
    return 1;
  }
  listener->run();
  std::cout << "incise-server: listening on " << (tls ? "https://" : "http://") << options.host
            << ":" << listener->port() << std::endl;
  // Forwarding speaks plain HTTP (server/http/forwarder.h): a node serving TLS itself registers
  // no address, and the others answer its sessions' calls with 503 rather than loop on a redirect.
  const auto node_address = tls ? std::string() : this_node_address(options, listener->port());
  if (tls) {
    std::cerr << "incise-server: serving TLS itself, this node is not reachable for forwarding; "
                 "run several nodes behind a TLS proxy (docs/scale_out.md)\n";
  } else {
    std::cerr << "incise-server: other nodes reach this one at " << node_address << "\n";
  }
  server::NodeHeartbeat heartbeat(
      pool, node_id, node_address, options.node_timeout_s, [&app] { return app->now(); },
      [&app](db::Database& db) { app->reconcile_station_links(db); });

  // Graceful shutdown: stop accepting, close agent links, give in-flight requests a moment.
  net::signal_set signals(ioc, SIGINT, SIGTERM);
  net::steady_timer grace(ioc);
  signals.async_wait([&](const boost::system::error_code& ec, int signal) {
    if (ec) return;
    std::cerr << "incise-server: caught signal " << signal << ", shutting down\n";
    listener->stop();
    app->close_all_agents();
    // Each live session closes its recording and stores its score before the process ends.
    app->live_sessions().stop_all("server shutting down");
    grace.expires_after(std::chrono::milliseconds(500));
    grace.async_wait([&](const boost::system::error_code&) { ioc.stop(); });
  });

  // The last line of defence: every boundary catches its own parse errors, but an exception that
  // still escapes a handler must cost only that connection (whose handler chain it ended), not
  // the process and every live session in it. run() may be called again after it threw.
  const auto run_io = [&ioc] {
    for (;;) {
      try {
        ioc.run();
        return;
      } catch (const std::exception& e) {
        std::cerr << "incise-server: internal error escaped a connection handler: "
                  << server::valid_utf8(e.what()) << "\n";
      } catch (...) {
        std::cerr << "incise-server: unknown error escaped a connection handler\n";
      }
    }
  };
  std::vector<std::thread> threads;
  for (int i = 1; i < options.threads; ++i)
    threads.emplace_back(run_io);
  run_io();
  for (auto& t : threads)
    t.join();
  // Before the I/O context goes: a finishing login or long read posts its answer to it.
  app->password_workers().stop();
  app->long_reads().stop();
  std::cerr << "incise-server: stopped\n";
  return 0;
}
