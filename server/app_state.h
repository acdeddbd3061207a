#pragma once
// What every connection of one server shares (Beast chat-multi's shared_state): the database's
// connection pool, the web root, the live station registry and the login limiter. A request leases
// a connection for as long as it runs (ApiContext::db()); requests run side by side, and what
// must hold across statements holds by transactions, not by a lock of ours.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "db/connection_pool.h"
#include "server/calibration_runner.h"
#include "server/live_sessions.h"
#include "server/login_limiter.h"
#include "server/replay_slots.h"
#include "server/worker_pool.h"

namespace incise::server {

class AgentSession;
class ViewSession;

struct ServerConfig {
  std::filesystem::path web_root;  // the built dashboard (web/dist)
  db::DatabaseUrl database;        // where the data lives; live sessions open their own connection
  std::string node_id;             // this node's name among those sharing the database
  int node_timeout_s = 30;         // --node-timeout: a node silent this long is taken for dead
  std::int64_t session_ttl_s = 12 * 3600;
  std::size_t api_body_limit = 64 * 1024;
  bool secure_cookies = false;  // set behind TLS
  bool demo = false;            // --demo: the demo stations' public tokens are accepted
  std::string trusted_proxy;    // --trusted-proxy (server_options.h, request_client)
};

class AppState {
 public:
  AppState(db::ConnectionPool& pool, ServerConfig config);
  ~AppState();

  db::ConnectionPool& pool() { return pool_; }
  const ServerConfig& config() const { return config_; }
  LoginLimiter& login_limiter() { return login_limiter_; }
  WorkerPool& password_workers() { return password_workers_; }
  WorkerPool& long_reads() { return long_reads_; }
  ReplaySlots& replay_slots() { return replay_slots_; }
  // This node's tissue calibration jobs (calibration_runner.h).
  CalibrationRunner& calibration_runner() { return calibration_runner_; }

  // Unix seconds; replaceable so that tests can move time.
  std::int64_t now() const { return clock_(); }
  void set_clock(std::function<std::int64_t()> clock) { clock_ = std::move(clock); }

  // Wrong station tokens per address (server/agent_session.h).
  LoginLimiter& agent_limiter() { return agent_limiter_; }

  // Station agents currently connected, one per station. Registers `session` for the station
  // and returns "" or, when another live link holds the station, refuses and returns that link's
  // address.
  std::string agent_try_join(std::int64_t station_id, const std::shared_ptr<AgentSession>& session);
  void agent_left(const AgentSession* session);
  bool station_online(std::int64_t station_id) const;
  // The shared database's record of which node holds a station's link (docs/scale_out.md):
  // claims it for this node and returns "", or returns the live node that holds it. Throws on a
  // database error.
  std::string link_station_here(std::int64_t station_id);
  // Drops this node's claim on the station once no link to it is left here. Never throws.
  void unlink_station_if_gone(std::int64_t station_id) noexcept;
  // After each heartbeat: the database's links of this node made to match the links it holds
  // (db::NodesRepo::reconcile_links), should an unlink have failed or a sweep have taken them.
  void reconcile_station_links(db::Database& db);
  // Whether the station's agent is linked here or to another live node (read on `db`).
  bool station_online_anywhere(db::Database& db, std::int64_t station_id);
  // The stations linked here or to another live node, ascending.
  std::vector<std::int64_t> stations_online_anywhere(db::Database& db);
  // The station's most recently connected agent, or nullptr.
  std::shared_ptr<AgentSession> agent_for_station(std::int64_t station_id) const;
  // Closes every agent link (shutdown).
  void close_all_agents();

  LiveSessions& live_sessions() { return live_sessions_; }

  // The open view WebSockets (live and replay) by the user who opened them, so that disabling a
  // user or resetting their password also ends what they are watching. Thread-safe.
  void view_opened(std::int64_t user_id, const std::shared_ptr<ViewSession>& view);
  // Closes every open view of `user_id` with 1008 and `reason`; returns how many.
  int close_views_of(std::int64_t user_id, const std::string& reason);

 private:
  db::ConnectionPool& pool_;
  ServerConfig config_;
  LoginLimiter login_limiter_;
  LoginLimiter agent_limiter_;
  WorkerPool password_workers_{"password worker"};
  WorkerPool long_reads_{"long read", 0, 32};
  ReplaySlots replay_slots_;
  std::function<std::int64_t()> clock_;
  CalibrationRunner calibration_runner_;
  mutable std::mutex agents_mutex_;
  // Held across a look at the links here and the database's record of them, so that a reconnect
  // and the old link's unlink cannot interleave (the unlink would drop the new link's row).
  // Taken before agents_mutex_, never after.
  std::mutex links_mutex_;
  struct AgentEntry {
    std::int64_t station_id;
    std::weak_ptr<AgentSession> session;
    std::uint64_t joined = 0;  // join order, to find the newest agent of a station
  };
  std::uint64_t joins_ = 0;
  bool station_online_locked(std::int64_t station_id) const;  // agents_mutex_ held
  std::mutex views_mutex_;
  std::multimap<std::int64_t, std::weak_ptr<ViewSession>> views_;
  // Last, so that it goes first: its sessions use the members above until they stop.
  LiveSessions live_sessions_;
  std::map<const AgentSession*, AgentEntry> agents_;
};

}  // namespace incise::server
