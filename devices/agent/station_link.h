#pragma once
// One connection to the server's /agent WebSocket, from resolve to close: hello, welcome, then
// device-state frames at a fixed rate. The Agent makes a new StationLink per attempt and decides
// what to do when one ends.
//
// All work runs on the io_context's single thread; stop() may be called from any thread.

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

#include "devices/agent/options.h"
#include "devices/device.h"
#include "devices/protocol.h"

namespace incise::devices::agent {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using Clock = std::chrono::steady_clock;

struct LinkEnd {
  enum class Kind {
    Failed,   // never got a welcome: unreachable, timed out, dropped during the handshake
    Refused,  // the server said no (close 1008, HTTP 401/403): retrying cannot help
    Dropped,  // was connected, then lost the link
    Stopped,  // stop() was called; closed normally
  };
  Kind kind = Kind::Failed;
  std::string reason;               // e.g. "connect: Connection refused"
  uint64_t messages_sent = 0;       // device-state frames written on this link
  Clock::duration connected_for{};  // welcome to end; zero if never welcomed
};

struct LinkSettings {
  ServerAddress server;
  Hello hello;
  Clock::duration send_period{};
  Clock::time_point epoch;  // t = 0 of device polls and frame timestamps
};

class StationLink : public std::enable_shared_from_this<StationLink> {
 public:
  using WelcomeHandler = std::function<void(const Welcome&)>;
  using EndHandler = std::function<void(const LinkEnd&)>;

  // device and the handlers must outlive the link. on_end is called exactly once.
  StationLink(asio::io_context& io, const LinkSettings& settings, Device& device,
              WelcomeHandler on_welcome, EndHandler on_end);

  void run();
  // Closes with 1000 (normal) if connected, else abandons the attempt; on_end reports Stopped.
  void stop();

 private:
  void do_resolve();
  void on_resolve(beast::error_code ec, asio::ip::tcp::resolver::results_type results);
  void on_connect(beast::error_code ec, asio::ip::tcp::endpoint endpoint);
  void on_handshake(beast::error_code ec);
  void on_hello_sent(beast::error_code ec, std::size_t bytes);
  void on_welcome(beast::error_code ec, std::size_t bytes);
  void on_welcome_timeout(beast::error_code ec);
  void do_tick();
  void on_tick(beast::error_code ec);
  void do_send();
  void on_sent(beast::error_code ec, std::size_t bytes);
  void do_read();
  void on_read(beast::error_code ec, std::size_t bytes);
  void do_stop();
  void do_close();
  void on_close(beast::error_code ec);

  void fail(beast::error_code ec, const char* what);
  void finish(LinkEnd::Kind kind, std::string reason);

  LinkSettings settings_;
  Device& device_;
  WelcomeHandler on_welcome_;
  EndHandler on_end_;

  asio::ip::tcp::resolver resolver_;
  websocket::stream<beast::tcp_stream> ws_;
  websocket::response_type upgrade_response_;
  beast::flat_buffer read_buffer_;
  asio::steady_timer welcome_timer_;
  asio::steady_timer tick_timer_;
  std::string hello_text_;
  std::array<uint8_t, kDeviceStateFrameSize> frame_{};  // the one buffer every frame reuses

  bool ws_open_ = false;
  bool welcomed_ = false;
  bool welcome_timed_out_ = false;
  bool write_in_flight_ = false;
  bool stopping_ = false;
  bool closing_ = false;
  bool finished_ = false;
  uint32_t sequence_ = 0;
  uint64_t messages_sent_ = 0;
  Clock::time_point next_send_;
  Clock::time_point welcomed_at_;
};

}  // namespace incise::devices::agent
