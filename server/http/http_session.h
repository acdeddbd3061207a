#pragma once
// One HTTP connection (Beast chat-multi's `http_session`): reads a request with a body limit and
// a timeout, answers it, and hands WebSocket upgrades to the matching WebSocket session.
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <memory>
#include <optional>

#include "server/api/api_context.h"
#include "server/app_state.h"

namespace incise::server {

// The headers every HTTP response carries (docs/security.md): a Content-Security-Policy without
// inline scripts and with frame-ancestors 'none', X-Frame-Options, nosniff and Referrer-Policy.
void set_security_headers(Response& response);

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(boost::asio::ip::tcp::socket&& socket, std::shared_ptr<AppState> app);
  void run();

 private:
  void do_read();
  void on_read(boost::beast::error_code ec, std::size_t bytes);
  void send(Response&& response);
  void on_write(bool keep_alive, boost::beast::error_code ec, std::size_t bytes);
  void do_close();

  boost::beast::tcp_stream stream_;
  boost::beast::flat_buffer buffer_;
  std::shared_ptr<AppState> app_;
  std::optional<http::request_parser<http::string_body>> parser_;
  std::shared_ptr<Response> response_;  // kept alive while it is written
  std::string client_;
};

}  // namespace incise::server
