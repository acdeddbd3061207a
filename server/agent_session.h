#pragma once
// A station agent's WebSocket (/agent). Protocol (docs/api.md, devices/protocol.h): the agent
// says hello with its station token; the server answers welcome or closes with 1008 and the
// reason; then binary DeviceState frames follow. A malformed frame closes this link with 1007 and
// the decoder's reason; other connections are never disturbed.
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <cstdint>
#include <memory>
#include <string>

#include "server/app_state.h"

namespace incise::server {

class AgentSession : public std::enable_shared_from_this<AgentSession> {
 public:
  AgentSession(boost::asio::ip::tcp::socket&& socket, std::shared_ptr<AppState> app);
  ~AgentSession();

  void run(boost::beast::http::request<boost::beast::http::string_body> upgrade);
  // Thread-safe: closes the link with 1001 (going away) and `reason`.
  void close(std::string reason);

  std::int64_t device_states_received() const { return states_received_; }

 private:
  void on_accept(boost::beast::error_code ec);
  void do_read();
  void on_read(boost::beast::error_code ec, std::size_t bytes);
  void handle_hello();
  void handle_device_state();
  void do_close(boost::beast::websocket::close_code code, std::string reason);
  void on_write(boost::beast::error_code ec, std::size_t bytes);

  boost::beast::websocket::stream<boost::beast::tcp_stream> ws_;
  boost::beast::flat_buffer buffer_;
  std::shared_ptr<AppState> app_;
  std::string outgoing_;  // the welcome; one write in flight at most
  std::int64_t station_id_ = 0;
  bool closing_ = false;
  std::int64_t states_received_ = 0;
  std::uint32_t last_sequence_ = 0;
};

}  // namespace incise::server
