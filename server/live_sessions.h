#pragma once
// The live sessions this server runs, by session and by station, and the routing between them and
// the station agents: device states go to the station's running session, an agent dropping out
// pauses it.
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "devices/device_state.h"
#include "server/live/live_session.h"

namespace incise::server {

class LiveSessions {
 public:
  void add(const std::shared_ptr<live::LiveSession>& session);
  void remove(std::int64_t session_id);
  std::shared_ptr<live::LiveSession> find(std::int64_t session_id) const;
  // The station's session that has not finished, if any.
  std::shared_ptr<live::LiveSession> active_at(std::int64_t station_id) const;
  // Claims the station for a session being started, so that two starts racing for it (on
  // different threads; there is no global lock) cannot both pass the check: false while a session
  // is active there or another start holds the claim. add() of a session at the station, or
  // release_claim(), ends the claim.
  bool claim(std::int64_t station_id);
  void release_claim(std::int64_t station_id);
  // Whether a start holds the station's claim now.
  bool starting(std::int64_t station_id) const;

  // The agent's link report (with the server's loss_up) for the station's active session.
  void on_link_report(std::int64_t station_id, nlohmann::json report) const;
  void on_device_state(std::int64_t station_id, const devices::DeviceState& state,
                       std::uint64_t timestamp_us) const;
  void on_agent(std::int64_t station_id, bool online) const;
  // Stops every session (shutdown) and forgets them.
  void stop_all(const std::string& reason);

 private:
  mutable std::mutex mutex_;
  std::map<std::int64_t, std::shared_ptr<live::LiveSession>> sessions_;
  std::set<std::int64_t> claimed_;  // stations with a session being started
};

}  // namespace incise::server
