#pragma once
// Dispatches one /api request to its handler and turns every failure into a JSON error with the
// right status (docs/api.md). Never throws.
#include <string>
#include <string_view>

#include "server/api/api_context.h"

namespace incise::server {

Response handle_api_request(const Request& request, AppState& app, const Caller& caller);

// Whether the request carries an Origin other than the Host it was sent to (a page of another site,
// or of another port of this host). Browsers always send Origin on WebSocket upgrades.
bool is_cross_origin(const Request& request);
// Whether a Content-Type header names JSON (parameters such as a charset allowed).
bool is_json_media_type(std::string_view content_type);

// A JSON error response, `{"error": message}`, with the message made valid UTF-8 and cut to
// 512 bytes (it may echo a client's bytes). Never throws (a failed allocation still answers a
// fixed error body).
Response json_error(http::status status, std::string_view message, unsigned version,
                    bool keep_alive);

}  // namespace incise::server
