#include "server/http/http_session.h"

#include <algorithm>
#include <boost/beast/websocket.hpp>
#include <chrono>

#include "server/agent_session.h"
#include "server/api/forwarding.h"
#include "server/api/router.h"
#include "server/api/view_endpoints.h"
#include "server/http/forwarder.h"
#include "server/http/static_files.h"
#include "server/server_options.h"
#include "server/view_session.h"
#include "server/wire_text.h"

namespace incise::server {

namespace beast = boost::beast;
namespace net = boost::asio;

namespace {
constexpr auto kReadTimeout = std::chrono::seconds(30);
constexpr auto kUploadReadTimeout = std::chrono::seconds(300);
constexpr auto kWriteTimeout = std::chrono::seconds(30);
// A TLS handshake is a few round trips; a client that stalls in it holds a socket, nothing more.
constexpr auto kHandshakeTimeout = std::chrono::seconds(10);
constexpr auto kShutdownTimeout = std::chrono::seconds(5);
constexpr std::size_t kHeaderLimit = 16 * 1024;

// A request target is printable ASCII (RFC 9112 section 3.2, RFC 3986): any other byte is
// percent-encoded by every real client. Beast's parser lets bytes 0x80..0xFF through.
bool is_printable_ascii(std::string_view text) {
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x21 || byte > 0x7E) return false;
  }
  return true;
}

// Plain HTTP on the HTTPS port: a page fetch goes to the same place under https://; anything else
// (a login sent in the clear among it) is refused, not followed anywhere.
Response redirect_to_https(const Request& request) {
  const auto host = request[http::field::host];
  const bool fetch = request.method() == http::verb::get || request.method() == http::verb::head;
  // An origin-form target only ("/..."): "@elsewhere/" would make the Location another host.
  const bool redirect =
      fetch && !host.empty() && is_printable_ascii(host) && request.target().starts_with('/');
  Response response =
      json_error(redirect ? http::status::moved_permanently : http::status::bad_request,
                 "this port speaks HTTPS only; use https://", request.version(), false);
  if (!redirect) return response;
  response.set(http::field::location,
               "https://" + std::string(host) + std::string(request.target()));
  if (request.method() == http::verb::head) {
    response.body().clear();
    response.prepare_payload();
  }
  return response;
}

}  // namespace

void refuse_websocket(transport::MaybeTlsStream&& stream, Request&& upgrade,
                      beast::websocket::close_code code, std::string reason) {
  using Ws = beast::websocket::stream<transport::MaybeTlsStream>;
  auto ws = std::make_shared<Ws>(std::move(stream));
  ws->set_option(beast::websocket::stream_base::timeout::suggested(beast::role_type::server));
  auto request = std::make_shared<Request>(std::move(upgrade));
  ws->async_accept(
      *request, [ws, request, code, reason = close_reason_text(reason)](beast::error_code ec) {
        if (ec) return;
        ws->async_close(beast::websocket::close_reason(code, reason), [ws](beast::error_code) {});
      });
}

bool checks_password(const Request& request) {
  if (request.method() != http::verb::post) return false;
  const std::string_view target(request.target().data(), request.target().size());
  const std::string_view path = target.substr(0, target.find('?'));
  if (path == "/api/login" || path == "/api/me/password" || path == "/api/users") return true;
  // POST /api/users/{id}/password (an admin's reset)
  constexpr std::string_view users = "/api/users/", password = "/password";
  if (!path.starts_with(users) || !path.ends_with(password)) return false;
  const std::string_view rest = path.substr(users.size());  // "{id}/password"
  return rest.size() > password.size() &&
         rest.substr(0, rest.size() - password.size()).find('/') == std::string_view::npos;
}

HttpSession::HttpSession(net::ip::tcp::socket&& socket, std::shared_ptr<AppState> app,
                         net::ssl::context* tls)
    : stream_(transport::make_stream(beast::tcp_stream(std::move(socket)), tls)),
      app_(std::move(app)) {
  beast::error_code ec;
  const auto remote = stream_.tcp().socket().remote_endpoint(ec);
  client_ = ec ? "unknown" : remote.address().to_string();
}

void HttpSession::run() {
  net::dispatch(stream_.get_executor(), [self = shared_from_this()] {
    if (!self->stream_.is_tls()) return self->do_read();
    // On the HTTPS port, a browser sent to http:// speaks plain HTTP: the first bytes tell.
    self->stream_.tcp().expires_after(kHandshakeTimeout);
    beast::async_detect_ssl(self->stream_.tcp(), self->buffer_,
                            beast::bind_front_handler(&HttpSession::on_detect, self));
  });
}

void HttpSession::on_detect(beast::error_code ec, bool tls) {
  if (ec) return stream_.tcp().close();
  if (!tls) {
    // Answered in plain text, the only thing it can read: where to go (redirect_to_https).
    plain_on_tls_port_ = true;
    stream_.become_plain();
    return do_read();
  }
  stream_.async_handshake(net::ssl::stream_base::server, buffer_.data(),
                          [self = shared_from_this()](beast::error_code ec, std::size_t used) {
                            self->buffer_.consume(used);
                            self->on_handshake(ec);
                          });
}

void HttpSession::on_handshake(beast::error_code ec) {
  // An untrusted certificate at the client, an old protocol, a scanner: nothing to answer in
  // (there is no TLS session), so the connection just ends.
  if (ec) return stream_.tcp().close();
  do_read();
}

std::size_t body_limit_for(http::verb method, std::string_view target, const ServerConfig& config) {
  // A calibration's data file travels as the job's JSON (docs/calibration.md).
  const auto path = target.substr(0, target.find('?'));
  if (method == http::verb::post && path == "/api/calibration/jobs") return kUploadBodyLimit;
  return config.api_body_limit;
}

void HttpSession::do_read() {
  parser_.emplace();
  parser_->header_limit(kHeaderLimit);
  // The header first: its target decides how large a body may be (an upload's, or the API's).
  // Beast checks a Content-Length against the limit as the header ends, so the header is read
  // under the largest limit and the request's own is applied in on_header.
  parser_->body_limit(std::max(kUploadBodyLimit, app_->config().api_body_limit));
  stream_.tcp().expires_after(kReadTimeout);
  http::async_read_header(stream_, buffer_, *parser_,
                          beast::bind_front_handler(&HttpSession::on_header, shared_from_this()));
}

void HttpSession::on_header(beast::error_code ec, std::size_t bytes) {
  if (ec) return on_read(ec, bytes);
  const std::size_t limit =
      body_limit_for(parser_->get().method(), parser_->get().target(), app_->config());
  const auto length = parser_->content_length();
  if (length && *length > limit) return on_read(http::error::body_limit, bytes);
  parser_->body_limit(limit);  // a chunked body counts against it as it comes
  // 8 MiB take longer than the API's small bodies on a slow link.
  if (limit > app_->config().api_body_limit) stream_.tcp().expires_after(kUploadReadTimeout);
  http::async_read(stream_, buffer_, *parser_,
                   beast::bind_front_handler(&HttpSession::on_read, shared_from_this()));
}

void HttpSession::on_read(beast::error_code ec, std::size_t) {
  if (ec == http::error::end_of_stream || ec == beast::error::timeout ||
      transport::is_truncation(ec)) {
    return do_close();
  }
  if (ec == http::error::body_limit) {
    // The rest of the body is still on the wire, so the connection cannot be reused.
    return send(
        json_error(http::status::payload_too_large,
                   "request body exceeds " +
                       std::to_string(body_limit_for(parser_->get().method(),
                                                     parser_->get().target(), app_->config()) /
                                      1024) +
                       " KiB",
                   11, false));
  }
  if (ec) {
    if (ec != net::error::operation_aborted && ec != net::error::connection_reset) {
      return send(json_error(http::status::bad_request, "malformed HTTP request: " + ec.message(),
                             11, false));
    }
    return do_close();
  }

  const auto& request = parser_->get();
  const auto target = request.target();
  const auto& config = app_->config();
  caller_.address = request_client(client_, request["X-Forwarded-For"], config.trusted_proxy);
  caller_.https = reached_over_tls(stream_.is_tls(), client_, request["X-Forwarded-Proto"],
                                   config.trusted_proxy);
  if (auto refusal = refuse_request(request)) return send(std::move(*refusal));
  if (plain_on_tls_port_) return send(redirect_to_https(request));
  if (auto owner = forward_target(request, *app_)) return forward(*owner);
  if (beast::websocket::is_upgrade(request)) {
    // From here on the stream belongs to the WebSocket session (which keeps its own timeouts);
    // this HttpSession ends when this handler returns.
    stream_.tcp().expires_never();
    if (target == "/agent") {
      return std::make_shared<AgentSession>(std::move(stream_), app_)->run(parser_->release());
    }
    if (is_view_path(target)) {
      if (!is_replay_path(target)) return open_view(resolve_view(request, *app_, caller_.address));
      // A replay reads its whole recording first: on a long-read worker, like a review.
      auto job = [self = shared_from_this()] {
        auto resolved = resolve_view(self->parser_->get(), *self->app_, self->caller_.address);
        net::post(self->stream_.get_executor(), [self, resolved = std::move(resolved)]() mutable {
          self->open_view(std::move(resolved));
        });
      };
      if (app_->long_reads().try_post(std::move(job))) return;
      return refuse_websocket(std::move(stream_), parser_->release(),
                              beast::websocket::close_code::try_again_later,
                              "too many recordings are being read; try again in a moment");
    }
    return send(json_error(http::status::not_found,
                           "no WebSocket endpoint at " + std::string(target), 11, false));
  }
  if (checks_password(request)) {
    return answer_on(app_->password_workers(),
                     "too many passwords are being checked; try again in a moment");
  }
  if (is_long_read(request)) {
    return answer_on(app_->long_reads(), "too many long reads at once; try again in a moment");
  }
  send(answer_request(request, *app_, caller_));
}

void HttpSession::open_view(std::variant<ViewTarget, Response>&& resolved) {
  if (auto* error = std::get_if<Response>(&resolved)) return send(std::move(*error));
  auto& view = std::get<ViewTarget>(resolved);
  if (!view.busy.empty()) {
    return refuse_websocket(std::move(stream_), parser_->release(),
                            beast::websocket::close_code::try_again_later, view.busy);
  }
  auto session = view.replay
                     ? std::make_shared<ViewSession>(std::move(stream_), std::move(view.replay),
                                                     view.outside_view_allowed)
                     : std::make_shared<ViewSession>(std::move(stream_), std::move(view.live),
                                                     view.outside_view_allowed);
  session->hold(std::move(view.replay_slot));
  app_->view_opened(view.user_id, session);
  session->run(parser_->release());
}

bool is_long_read(const Request& request) {
  const std::string_view target(request.target().data(), request.target().size());
  const auto path = target.substr(0, target.find('?'));
  // An upload: up to 8 MiB of JSON and CSV parsed and stored.
  if (request.method() == http::verb::post && path == "/api/calibration/jobs") return true;
  if (request.method() != http::verb::get) return false;
  if (path == "/api/exports/scores.csv") return true;
  // GET /api/sessions/{id}/review
  constexpr std::string_view sessions = "/api/sessions/", review = "/review";
  if (!path.starts_with(sessions) || !path.ends_with(review)) return false;
  const auto id = path.substr(sessions.size(), path.size() - sessions.size() - review.size());
  return !id.empty() && id.find('/') == std::string_view::npos;
}

std::optional<Response> refuse_request(const Request& request) {
  if (!is_printable_ascii(request.target())) {
    // Refused before anything routes, echoes or upgrades on it; the connection stays usable.
    return json_error(http::status::bad_request,
                      "the request target must be printable ASCII (percent-encode other bytes)",
                      request.version(), request.keep_alive());
  }
  if (request.version() >= 11 && request[http::field::host].empty()) {
    // RFC 9112 section 3.2: a server must answer 400 to an HTTP/1.1 request without Host. The
    // origin checks (CSRF, the WebSocket upgrades) compare against it.
    return json_error(http::status::bad_request, "a Host header is required (HTTP/1.1)",
                      request.version(), request.keep_alive());
  }
  return std::nullopt;
}

bool is_api_target(std::string_view target) {
  const auto path = target.substr(0, target.find('?'));
  return path == "/api" || path.starts_with("/api/");
}

Response answer_request(const Request& request, AppState& app, const Caller& caller) {
  if (is_api_target(request.target())) {
    return handle_api_request(request, app, caller);
  }
  return serve_static(request, app.config().web_root);
}

void HttpSession::forward(const ForwardTarget& owner) {
  // The owner believes these from a node in its --trusted-proxy range: the client as this node
  // resolved it (last in the list), and whether the browser used HTTPS.
  auto& request = parser_->get();
  const auto forwarded_for = request["X-Forwarded-For"];
  request.set("X-Forwarded-For", forwarded_for.empty()
                                     ? caller_.address
                                     : std::string(forwarded_for) + ", " + caller_.address);
  request.set("X-Forwarded-Proto", caller_.https ? "https" : "http");
  if (beast::websocket::is_upgrade(request)) {
    stream_.tcp().expires_never();
    return forward_websocket(std::move(stream_), std::move(buffer_), owner, app_->config().node_id,
                             parser_->release());
  }
  forward_http(stream_.get_executor(), owner, app_->config().node_id, parser_->release(),
               [self = shared_from_this()](Response answer) { self->send(std::move(answer)); });
}

void HttpSession::answer_on(WorkerPool& workers, std::string_view busy) {
  auto job = [self = shared_from_this()] {
    // No read is pending meanwhile, so the parsed request stays as it is.
    auto response = handle_api_request(self->parser_->get(), *self->app_, self->caller_);
    net::post(self->stream_.get_executor(), [self, response = std::move(response)]() mutable {
      self->send(std::move(response));
    });
  };
  if (workers.try_post(std::move(job))) return;
  auto refusal = json_error(http::status::service_unavailable, busy, parser_->get().version(),
                            parser_->get().keep_alive());
  refusal.set(http::field::retry_after, "1");
  send(std::move(refusal));
}

void set_security_headers(Response& response, bool tls) {
  // The dashboard loads only its own scripts, styles, images and sockets (no inline script: Vite
  // emits modules); no page may frame it (clickjacking); no response is sniffed into another type;
  // no address leaves in a Referer. React and uPlot set styles through the CSSOM, which
  // style-src does not govern; a canvas draws decoded frames from blobs.
  response.set("Content-Security-Policy",
               "default-src 'self'; script-src 'self'; style-src 'self'; img-src 'self' data: "
               "blob:; connect-src 'self'; object-src 'none'; base-uri 'none'; form-action "
               "'self'; frame-ancestors 'none'");
  response.set("X-Frame-Options", "DENY");
  response.set("X-Content-Type-Options", "nosniff");
  response.set("Referrer-Policy", "no-referrer");
  // Once a browser has reached us over TLS it never falls back to plain HTTP for a year (RFC
  // 6797). Not over plain HTTP, where an attacker could have written it; a TLS proxy in front
  // sets its own.
  if (tls) response.set(http::field::strict_transport_security, "max-age=31536000");
}

void HttpSession::send(Response&& response) {
  // The answer may come long after the read's deadline was set (a long read, a forwarded call).
  stream_.tcp().expires_after(kWriteTimeout);
  response_ = std::make_shared<Response>(std::move(response));
  response_->set(http::field::server, "incise-server");
  set_security_headers(*response_, stream_.is_tls());
  const bool keep_alive = response_->keep_alive();
  http::async_write(
      stream_, *response_,
      beast::bind_front_handler(&HttpSession::on_write, shared_from_this(), keep_alive));
}

void HttpSession::on_write(bool keep_alive, beast::error_code ec, std::size_t) {
  response_.reset();
  if (ec || !keep_alive) return do_close();
  do_read();
}

void HttpSession::do_close() {
  if (auto* tls = stream_.tls()) {
    // close_notify, then the socket: the peer can tell a complete response from a cut one.
    stream_.tcp().expires_after(kShutdownTimeout);
    return tls->async_shutdown(
        [self = shared_from_this()](beast::error_code) { self->stream_.tcp().close(); });
  }
  beast::error_code ignored;
  stream_.tcp().socket().shutdown(net::ip::tcp::socket::shutdown_send, ignored);
}

}  // namespace incise::server
