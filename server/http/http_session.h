#pragma once
// One HTTP connection (Beast chat-multi's `http_session`): reads a request with a body limit and
// a timeout, answers it, and hands WebSocket upgrades to the matching WebSocket session. Over TLS
// when the server has a certificate: the handshake comes first, under its own deadline.
#include <boost/asio.hpp>
#include <boost/asio/ssl/context.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket/rfc6455.hpp>
#include <memory>
#include <optional>
#include <string_view>
#include <variant>

#include "server/api/api_context.h"
#include "server/api/forwarding.h"
#include "server/api/view_endpoints.h"
#include "server/app_state.h"
#include "transport/maybe_tls_stream.h"

namespace incise::server {

// The headers every HTTP response carries (docs/security.md): a Content-Security-Policy without
// inline scripts and with frame-ancestors 'none', X-Frame-Options, nosniff and Referrer-Policy;
// over TLS also Strict-Transport-Security.
void set_security_headers(Response& response, bool tls);

// The checks every request passes before anything routes it: a printable-ASCII target, and Host
// on HTTP/1.1. The refusal, or nullopt.
std::optional<Response> refuse_request(const Request& request);
// Whether the request checks or hashes a password (POST /api/login, /api/me/password, /api/users,
// /api/users/{id}/password): such requests run on AppState::password_workers(), never on an I/O
// thread (argon2id takes about 50 ms).
bool checks_password(const Request& request);
// Whether the request reads a whole recording or table (GET /api/sessions/{id}/review, GET
// /api/exports/scores.csv) or takes an upload (POST /api/calibration/jobs): such requests run on
// AppState::long_reads(), never on an I/O thread.
// A replay's upgrade (/api/recordings/{id}/replay) loads its recording there too.
bool is_long_read(const Request& request);
// A request body may be this large: ServerConfig::api_body_limit, except for an upload (POST
// /api/calibration/jobs carries a calibration's data file), kUploadBodyLimit.
inline constexpr std::size_t kUploadBodyLimit = 8 * 1024 * 1024;
std::size_t body_limit_for(http::verb method, std::string_view target, const ServerConfig& config);
// Whether a request target is the REST API's (/api, /api/..., with any query): else a file.
bool is_api_target(std::string_view target);
// A plain (not upgrade, not password-checking) request that passed refuse_request: the REST API
// under /api, the dashboard's files elsewhere.
Response answer_request(const Request& request, AppState& app, const Caller& caller);

// Accepts a WebSocket upgrade only to close it at once with `code` and `reason`: a browser shows
// a close reason, never the body of a refused upgrade.
void refuse_websocket(transport::MaybeTlsStream&& stream, Request&& upgrade,
                      boost::beast::websocket::close_code code, std::string reason);

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  // `tls`: the server's TLS context, or null for plain HTTP. It outlives every session.
  HttpSession(boost::asio::ip::tcp::socket&& socket, std::shared_ptr<AppState> app,
              boost::asio::ssl::context* tls);
  void run();

 private:
  void on_detect(boost::beast::error_code ec, bool tls);
  void on_handshake(boost::beast::error_code ec);
  void do_read();
  void on_header(boost::beast::error_code ec, std::size_t bytes);
  void on_read(boost::beast::error_code ec, std::size_t bytes);
  // The request belongs to another node (server/api/forwarding.h): it answers, through here.
  void forward(const ForwardTarget& owner);
  // Logins and long reads: handled on `workers`, answered back on this connection's strand; 503
  // with Retry-After and `busy` when its queue is full.
  void answer_on(WorkerPool& workers, std::string_view busy);
  // A view WebSocket, resolved (server/api/view_endpoints.h): opened, or refused.
  void open_view(std::variant<ViewTarget, Response>&& resolved);
  void send(Response&& response);
  void on_write(bool keep_alive, boost::beast::error_code ec, std::size_t bytes);
  void do_close();

  transport::MaybeTlsStream stream_;
  boost::beast::flat_buffer buffer_;
  std::shared_ptr<AppState> app_;
  std::optional<http::request_parser<http::string_body>> parser_;
  std::shared_ptr<Response> response_;  // kept alive while it is written
  std::string client_;                  // the peer's address
  Caller caller_;                       // the current request's (behind a trusted proxy)
  bool plain_on_tls_port_ = false;      // a plain-HTTP client on the HTTPS port
};

}  // namespace incise::server
