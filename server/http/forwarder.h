#pragma once
// Forwarding a request to the node that should answer it (server/api/forwarding.h decides which):
// a reverse proxy in a few dozen lines of Beast, for the two kinds of call that can need it.
// - A plain HTTP request goes over a fresh connection (Connection: close), and the answer comes
//   back to the caller unchanged but for keep-alive; an unreachable node is a 503 with
//   Retry-After.
// - A WebSocket upgrade (a live view) goes over a fresh connection too; once the node has said
//   101, bytes are copied both ways until either side closes. An unreachable node closes the
//   browser's socket with 1013 (try again later).
// Node-to-node traffic is plain HTTP inside the cluster (docs/scale_out.md). The forwarded
// request keeps its Host, Origin and cookie, so the owner checks the caller exactly as this node
// would have; it carries kForwardedByHeader so that it is never forwarded again.
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <functional>

#include "server/api/api_context.h"
#include "server/api/forwarding.h"
#include "transport/maybe_tls_stream.h"

namespace incise::server {

// Sends `request` to `to` on `executor` (the caller's strand) and calls `done` there with the
// answer, or with a 503 of its own.
void forward_http(boost::asio::any_io_executor executor, const ForwardTarget& to,
                  const std::string& self_node, Request request,
                  std::function<void(Response)> done);

// Takes the browser's connection (`already_read`: bytes read past the upgrade request) and joins
// it to `to`'s answer to `upgrade`.
void forward_websocket(transport::MaybeTlsStream&& client, boost::beast::flat_buffer&& already_read,
                       const ForwardTarget& to, const std::string& self_node, Request&& upgrade);

}  // namespace incise::server
