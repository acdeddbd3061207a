#include "server/app_state.h"

#include <chrono>
#include <vector>

#include "server/agent_session.h"

namespace incise::server {

AppState::AppState(db::Database& db, ServerConfig config)
    : db_(db), config_(std::move(config)), clock_([] {
        return std::chrono::duration_cast<std::chrono::seconds>(
                   std::chrono::system_clock::now().time_since_epoch())
            .count();
      }) {}

AppState::~AppState() {
  // Sessions call back into the agent registry: end them while it still exists.
  live_sessions_.stop_all("server shutting down");
}

// The live session hears of agents joining and leaving under agents_mutex_, so that a leave and a
// join racing during a reconnect cannot leave it believing the station is offline. (Lock order:
// agents_mutex_, then LiveSessions, then a LiveSession; nothing takes them the other way round.)
void AppState::agent_joined(std::int64_t station_id, const std::shared_ptr<AgentSession>& session) {
  std::lock_guard lock(agents_mutex_);
  agents_[session.get()] = AgentEntry{station_id, session, ++joins_};
  live_sessions_.on_agent(station_id, true);
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

}  // namespace incise::server
