#pragma once
// Which node should answer a request (docs/scale_out.md). Every node serves every call from the
// shared database, except what lives in one node's memory: a live session (its view, pause,
// resume, stop, annotations while it runs) lives on the node that runs it, and a session can
// only start on, and a station's agent hears of changes from, the node that holds its link. Such a
// request reaching another node is forwarded there (server/http/forwarder.h), so that a browser
// never needs to know where a session runs.
#include <optional>
#include <string>

#include "server/api/api_context.h"
#include "server/app_state.h"

namespace incise::server {

// Set on a forwarded request: the node that forwarded it. A request that carries it is answered
// where it lands, never forwarded again (no loops, whatever the database says meanwhile).
inline constexpr const char* kForwardedByHeader = "X-Incise-Forwarded-By";

struct ForwardTarget {
  std::string node_id;
  std::string address;  // HOST:PORT, plain HTTP
};

// The other node that should answer `request`, or nullopt to answer it here:
// - /api/sessions/{id} and /api/sessions/{id}/... (the view WebSocket among them) while the
//   session is running or paused on another node;
// - POST /api/sessions whose JSON body names a station linked to another node, not here; and
//   any change to such a station (PATCH /api/stations/{id}, PUT .../calibration), which its
//   agent link must hear of.
// Reads the database; never throws (on any error the request is answered here).
std::optional<ForwardTarget> forward_target(const Request& request, AppState& app) noexcept;

}  // namespace incise::server
