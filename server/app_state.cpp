#include "server/app_state.h"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <vector>

#include "db/nodes_repo.h"
#include "server/agent_session.h"
#include "server/view_session.h"

namespace incise::server {

AppState::AppState(db::ConnectionPool& pool, ServerConfig config)
    : pool_(pool),
      config_(std::move(config)),
      // Ten wrong tokens from an address are free (a mistyped configuration), then the wait
      // doubles; ten quiet minutes forget them.
      agent_limiter_(LoginPolicy{.free_per_pair = 10,
                                 .free_per_address = 1 << 30,
                                 .free_per_account = 1 << 30,
                                 .max_wait_s = 300,
                                 .forget_after_s = 600}),
      clock_([] {
        return std::chrono::duration_cast<std::chrono::seconds>(
                   std::chrono::system_clock::now().time_since_epoch())
            .count();
      }),
      calibration_runner_(pool_, config_.node_id, [this] { return now(); }) {}

AppState::~AppState() {
  calibration_runner_.stop();
  // Sessions call back into the agent registry: end them while it still exists.
  live_sessions_.stop_all("server shutting down");
}

// The live session hears of agents joining and leaving under agents_mutex_, so that a leave and a
// join racing during a reconnect cannot leave it believing the station is offline. (Lock order:
// agents_mutex_, then LiveSessions, then a LiveSession; nothing takes them the other way round.)
std::string AppState::agent_try_join(std::int64_t station_id,
                                     const std::shared_ptr<AgentSession>& session) {
  std::lock_guard lock(agents_mutex_);
  for (const auto& [_, entry] : agents_) {
    if (entry.station_id != station_id) continue;
    const auto holder = entry.session.lock();
    if (holder && !holder->closing()) return holder->address();
  }
  agents_[session.get()] = AgentEntry{station_id, session, ++joins_};
  live_sessions_.on_agent(station_id, true);
  return {};
}

void AppState::agent_left(const AgentSession* session) {
  std::lock_guard lock(agents_mutex_);
  const auto it = agents_.find(session);
  if (it == agents_.end()) return;
  const auto station_id = it->second.station_id;
  agents_.erase(it);
  // During a reconnect the station may already have its new link: then it stays online.
  if (!station_online_locked(station_id)) live_sessions_.on_agent(station_id, false);
}

bool AppState::station_online_locked(std::int64_t station_id) const {
  for (const auto& [_, entry] : agents_) {
    if (entry.station_id == station_id) return true;
  }
  return false;
}

std::shared_ptr<AgentSession> AppState::agent_for_station(std::int64_t station_id) const {
  std::lock_guard lock(agents_mutex_);
  std::shared_ptr<AgentSession> newest;
  std::uint64_t newest_join = 0;
  for (const auto& [_, entry] : agents_) {
    if (entry.station_id != station_id || entry.joined < newest_join) continue;
    if (auto s = entry.session.lock()) {
      newest = std::move(s);
      newest_join = entry.joined;
    }
  }
  return newest;
}

std::string AppState::link_station_here(std::int64_t station_id) {
  std::lock_guard links(links_mutex_);
  auto db = pool_.acquire();
  return db::NodesRepo(*db).link_station(station_id, config_.node_id, now(),
                                         config_.node_timeout_s);
}

void AppState::unlink_station_if_gone(std::int64_t station_id) noexcept {
  try {
    std::lock_guard links(links_mutex_);
    if (station_online(station_id)) return;  // a reconnect here already holds it
    auto db = pool_.acquire();
    db::NodesRepo(*db).unlink_station(station_id, config_.node_id);
  } catch (const std::exception& e) {
    // Left behind, the row only makes other nodes forward a start here, which answers that the
    // station is offline; the heartbeat sweep drops it if this node dies.
    std::cerr << "incise-server: station " << station_id
              << ": cannot drop its link record: " << e.what() << "\n";
  } catch (...) {
  }
}

void AppState::reconcile_station_links(db::Database& db) {
  std::lock_guard links(links_mutex_);
  std::vector<std::int64_t> here;
  {
    std::lock_guard lock(agents_mutex_);
    for (const auto& [_, entry] : agents_)
      here.push_back(entry.station_id);
  }
  std::sort(here.begin(), here.end());
  here.erase(std::unique(here.begin(), here.end()), here.end());
  for (const auto station :
       db::NodesRepo(db).reconcile_links(config_.node_id, here, now(), config_.node_timeout_s)) {
    std::cerr << "incise-server: station " << station
              << " has an agent here and at another live node\n";
  }
}

bool AppState::station_online_anywhere(db::Database& db, std::int64_t station_id) {
  if (station_online(station_id)) return true;
  const auto node = db::NodesRepo(db).node_of_station(station_id);
  return node && node->heartbeat_at >= now() - config_.node_timeout_s;
}

std::vector<std::int64_t> AppState::stations_online_anywhere(db::Database& db) {
  auto online = db::NodesRepo(db).linked_stations(now(), config_.node_timeout_s);
  {
    std::lock_guard lock(agents_mutex_);
    for (const auto& [_, entry] : agents_)
      online.push_back(entry.station_id);
  }
  std::sort(online.begin(), online.end());
  online.erase(std::unique(online.begin(), online.end()), online.end());
  return online;
}

bool AppState::station_online(std::int64_t station_id) const {
  std::lock_guard lock(agents_mutex_);
  return station_online_locked(station_id);
}

void AppState::close_all_agents() {
  std::vector<std::shared_ptr<AgentSession>> live;
  {
    std::lock_guard lock(agents_mutex_);
    for (const auto& [_, entry] : agents_) {
      if (auto s = entry.session.lock()) live.push_back(std::move(s));
    }
  }
  for (const auto& s : live)
    s->close("server shutting down");
}

void AppState::view_opened(std::int64_t user_id, const std::shared_ptr<ViewSession>& view) {
  std::lock_guard lock(views_mutex_);
  std::erase_if(views_, [](const auto& entry) { return entry.second.expired(); });
  views_.emplace(user_id, view);
}

int AppState::close_views_of(std::int64_t user_id, const std::string& reason) {
  std::vector<std::shared_ptr<ViewSession>> open;
  {
    std::lock_guard lock(views_mutex_);
    const auto [first, last] = views_.equal_range(user_id);
    for (auto it = first; it != last; ++it) {
      if (auto view = it->second.lock()) open.push_back(std::move(view));
    }
    views_.erase(first, last);
  }
  for (const auto& view : open)
    view->close(boost::beast::websocket::close_code::policy_error, reason);
  return static_cast<int>(open.size());
}

}  // namespace incise::server
