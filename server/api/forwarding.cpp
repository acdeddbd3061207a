#include "server/api/forwarding.h"

#include <charconv>
#include <nlohmann/json.hpp>

#include "db/nodes_repo.h"
#include "server/server_options.h"

namespace incise::server {
namespace {

constexpr std::string_view kSessions = "/api/sessions";
constexpr std::string_view kStations = "/api/stations";

// With `collection` "/api/sessions": "/api/sessions/7" or "/api/sessions/7/anything" -> 7; else 0.
std::int64_t id_in_path(std::string_view path, std::string_view collection) {
  if (!path.starts_with(collection) || path.size() <= collection.size() + 1 ||
      path[collection.size()] != '/') {
    return 0;
  }
  const auto rest = path.substr(collection.size() + 1);
  const auto digits = rest.substr(0, rest.find('/'));
  std::int64_t id = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), id);
  return ec == std::errc{} && end == digits.data() + digits.size() && id > 0 ? id : 0;
}

// The station a session start names, or 0 (the handler then answers what is wrong with it).
std::int64_t station_of_start(const Request& request) {
  const auto body = nlohmann::json::parse(request.body(), nullptr, false);
  if (!body.is_object()) return 0;
  const auto it = body.find("station_id");
  if (it == body.end() || !it->is_number_integer()) return 0;
  return it->get<std::int64_t>();
}

// `node`, unless it is this one or has no usable address (a node serving TLS itself registers
// none). With `live_only`, also unless its heartbeat is stale: a dead node's station is offline.
std::optional<ForwardTarget> elsewhere(const std::optional<db::NodeRecord>& node, AppState& app,
                                       bool live_only) {
  if (!node || node->id == app.config().node_id || !is_node_address(node->address)) {
    return std::nullopt;
  }
  if (live_only && node->heartbeat_at < app.now() - app.config().node_timeout_s) {
    return std::nullopt;
  }
  return ForwardTarget{node->id, node->address};
}

}  // namespace

std::optional<ForwardTarget> forward_target(const Request& request, AppState& app) noexcept {
  try {
    if (request.count(kForwardedByHeader) > 0) return std::nullopt;
    const std::string_view target(request.target().data(), request.target().size());
    const auto path = target.substr(0, target.find('?'));
    if (const auto session = id_in_path(path, kSessions)) {
      auto db = app.pool().acquire();
      // Its node even when silent: 503 (try again) until the sweep ends the session.
      return elsewhere(db::NodesRepo(*db).node_of_live_session(session), app, false);
    }
    // A start, and a change to a station (retiring it closes its agent link; a new calibration
    // goes to its agent at once; neither while a session runs there): where its agent is.
    std::int64_t station = 0;
    if (path == kSessions && request.method() == http::verb::post) {
      station = station_of_start(request);
    } else if (request.method() != http::verb::get) {
      station = id_in_path(path, kStations);
    }
    if (station > 0) {
      if (app.station_online(station)) return std::nullopt;
      auto db = app.pool().acquire();
      return elsewhere(db::NodesRepo(*db).node_of_station(station), app, true);
    }
    return std::nullopt;
  } catch (...) {
    return std::nullopt;
  }
}

}  // namespace incise::server
