#pragma once
// Dispatches one /api request to its handler and turns every failure into a JSON error with the
// right status (docs/api.md). Never throws.
#include <string>

#include "server/api/api_context.h"

namespace incise::server {

Response handle_api_request(const Request& request, AppState& app, const std::string& client);

// Whether the request carries an Origin other than the Host it was sent to (a page of another site,
// or of another port of this host). Browsers always send Origin on WebSocket upgrades.
bool is_cross_origin(const Request& request);

// A JSON error response, `{"error": message}`.
Response json_error(http::status status, const std::string& message, unsigned version,
                    bool keep_alive);

}  // namespace incise::server
