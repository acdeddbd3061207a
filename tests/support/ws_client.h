#pragma once
// A minimal WebSocket client of the server's /agent endpoint (Boost.Beast), to play a station
// agent that misbehaves. Every operation has a timeout.
#include <boost/asio/io_context.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/websocket.hpp>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace incise::server::test {

// What one read brought: a message, or the close frame (or the error) that ended the link.
struct WsEvent {
  bool closed = false;
  std::string message;  // when !closed
  bool text = false;    // when !closed
  int close_code = 0;   // when closed by a close frame; 0 otherwise
  std::string close_reason;
  std::string error;  // the read's error when closed
};

class WsClient {
 public:
  // Connects and completes the WebSocket handshake on `target`; throws boost::system::system_error.
  // `headers` are added to the upgrade request (e.g. the login cookie).
  WsClient(const std::string& host, unsigned short port, const std::string& target = "/agent",
           const std::vector<std::pair<std::string, std::string>>& headers = {});
  ~WsClient();

  void send_text(const std::string& text);
  void send_binary(const std::vector<std::uint8_t>& bytes);
  WsEvent read();
  void close();

 private:
  void run_until(const bool& done);

  boost::asio::io_context io_;
  boost::beast::websocket::stream<boost::beast::tcp_stream> ws_;
  boost::beast::flat_buffer buffer_;
};

}  // namespace incise::server::test
