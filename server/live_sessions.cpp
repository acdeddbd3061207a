#include "server/live_sessions.h"

namespace incise::server {

void LiveSessions::add(const std::shared_ptr<live::LiveSession>& session) {
  std::vector<std::shared_ptr<live::LiveSession>> finished;  // destroyed outside the lock
  std::lock_guard lock(mutex_);
  // Sessions that ended by themselves (e.g. an unstable simulation) are forgotten here; their
  // records stay in the database.
  for (auto it = sessions_.begin(); it != sessions_.end();) {
    if (it->second->state() == live::LiveState::finished) {
      finished.push_back(std::move(it->second));
      it = sessions_.erase(it);
    } else {
      ++it;
    }
  }
  sessions_[session->session_id()] = session;
  claimed_.erase(session->station_id());
}

bool LiveSessions::claim(std::int64_t station_id) {
  std::lock_guard lock(mutex_);
  if (claimed_.count(station_id)) return false;
  for (const auto& [_, session] : sessions_) {
    if (session->station_id() == station_id && session->state() != live::LiveState::finished) {
      return false;
    }
  }
  claimed_.insert(station_id);
  return true;
}

bool LiveSessions::starting(std::int64_t station_id) const {
  std::lock_guard lock(mutex_);
  return claimed_.count(station_id) > 0;
}

void LiveSessions::release_claim(std::int64_t station_id) {
  std::lock_guard lock(mutex_);
  claimed_.erase(station_id);
}

void LiveSessions::remove(std::int64_t session_id) {
  std::shared_ptr<live::LiveSession> removed;  // destroyed outside the lock
  std::lock_guard lock(mutex_);
  if (auto it = sessions_.find(session_id); it != sessions_.end()) {
    removed = std::move(it->second);
    sessions_.erase(it);
  }
}

std::shared_ptr<live::LiveSession> LiveSessions::find(std::int64_t session_id) const {
  std::lock_guard lock(mutex_);
  const auto it = sessions_.find(session_id);
  return it == sessions_.end() ? nullptr : it->second;
}

std::shared_ptr<live::LiveSession> LiveSessions::active_at(std::int64_t station_id) const {
  std::lock_guard lock(mutex_);
  for (const auto& [_, session] : sessions_) {
    if (session->station_id() == station_id && session->state() != live::LiveState::finished) {
      return session;
    }
  }
  return nullptr;
}

void LiveSessions::on_link_report(std::int64_t station_id, nlohmann::json report) const {
  if (auto session = active_at(station_id)) session->set_link_report(std::move(report));
}

void LiveSessions::on_device_state(std::int64_t station_id, const devices::DeviceState& state,
                                   std::uint64_t timestamp_us) const {
  if (auto session = active_at(station_id)) session->on_device_state(state, timestamp_us);
}

void LiveSessions::on_agent(std::int64_t station_id, bool online) const {
  if (auto session = active_at(station_id)) session->set_agent_online(online);
}

void LiveSessions::stop_all(const std::string& reason) {
  std::map<std::int64_t, std::shared_ptr<live::LiveSession>> all;
  {
    std::lock_guard lock(mutex_);
    all.swap(sessions_);
  }
  for (auto& [_, session] : all)
    session->stop(reason);
}

}  // namespace incise::server
