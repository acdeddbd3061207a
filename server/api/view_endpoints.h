#pragma once
// The view WebSockets' doors (docs/api.md, "View WebSocket"): who may open which stream, checked
// on the upgrade request so that a refusal is a plain HTTP error with a JSON body.
#include <memory>
#include <optional>
#include <string>
#include <variant>

#include "server/api/api_context.h"
#include "server/live/live_session.h"
#include "server/live/replay_session.h"

namespace incise::server {

struct ViewTarget {
  std::shared_ptr<live::LiveSession> live;      // /api/sessions/{id}/view
  std::unique_ptr<live::ReplaySession> replay;  // /api/recordings/{id}/replay (not started)
  // Whether this viewer may switch to the view from outside the body (api::may_look_outside).
  bool outside_view_allowed = false;
  // The replay's slot (AppState::replay_slots), held by the view for as long as it is open.
  std::shared_ptr<void> replay_slot;
  // When no slot was free: why. The upgrade is accepted and closed with 1013 and this reason,
  // which the browser can show (it never sees an HTTP refusal of an upgrade).
  std::string busy;
  // Who opened it (AppState::view_opened).
  std::int64_t user_id = 0;
};

// Whether target is one of the view paths (so that other upgrades get a 404).
bool is_view_path(std::string_view target);
// Whether it is a replay's (/api/recordings/{id}/replay), which reads its whole recording first.
bool is_replay_path(std::string_view target);

// The stream to attach, or the error response (401/403/404/409) for the upgrade request.
// Leases a database connection itself, and gives it back before the replay is built.
std::variant<ViewTarget, Response> resolve_view(const Request& request, AppState& app,
                                                const std::string& client);

}  // namespace incise::server
