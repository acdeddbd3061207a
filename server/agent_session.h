#pragma once
// A station agent's WebSocket (/agent). Protocol (docs/api.md, devices/protocol.h): the agent
// says hello with its station token; the server answers welcome or closes with 1008 and the
// reason; then binary DeviceState frames follow, which go to the station's running session. The
// server sends binary ForceModel frames (the local force model) and JSON session notices back. A
// malformed frame closes this link with 1007 and the decoder's reason, a message over
// kMaxMessageSize with 1009 and the size; other connections are never disturbed.
// Hostile links (docs/security.md, "Station agents"): the hello must come within kHelloDeadline;
// wrong tokens are limited per address (AppState::agent_limiter); a station holds one link at a
// time, so a second hello with its token is closed with 1013 (try again later) while the first
// lives, and never takes the station over.
#include <array>
#include <atomic>
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>

#include "devices/protocol.h"
#include "server/app_state.h"
#include "transport/maybe_tls_stream.h"

namespace incise::server {

class AgentSession : public std::enable_shared_from_this<AgentSession> {
 public:
  AgentSession(transport::MaybeTlsStream&& stream, std::shared_ptr<AppState> app);
  ~AgentSession();

  void run(boost::beast::http::request<boost::beast::http::string_body> upgrade);
  // Thread-safe: closes the link with 1001 (going away) and `reason`.
  void close(std::string reason);

  // Thread-safe. Only the newest force model waits to be sent: a slow link gets fewer, never a
  // queue.
  void send_force_model(const devices::ForceModel& model);
  // Thread-safe: a JSON text message (session notices); at most kMaxQueuedTexts wait.
  void send_text(std::string text);

  std::int64_t device_states_received() const { return states_received_; }
  const std::string& address() const { return address_; }
  // Thread-safe: whether this link is being closed (it no longer holds its station).
  bool closing() const { return closing_; }

  static constexpr std::chrono::seconds kHelloDeadline{5};

 private:
  void on_accept(boost::beast::error_code ec);
  void do_read();
  void on_read(boost::beast::error_code ec, std::size_t bytes);
  void handle_hello();
  void on_hello_deadline(boost::beast::error_code ec);
  void handle_device_state();
  void handle_text();
  void do_close(boost::beast::websocket::close_code code, std::string reason);
  void do_write();
  void on_write(boost::beast::error_code ec, std::size_t bytes);

  static constexpr std::size_t kMaxQueuedTexts = 8;

  boost::beast::websocket::stream<transport::MaybeTlsStream> ws_;
  boost::beast::flat_buffer buffer_;
  std::shared_ptr<AppState> app_;
  std::string address_;  // the remote address, for the logs and the wrong-token limit
  boost::asio::steady_timer hello_timer_;
  // Writes: one in flight at most; texts first, then the newest force model.
  bool writing_ = false;
  std::deque<std::string> texts_;
  std::string text_in_flight_;
  // The newest force model per device; one hand never displaces the other's.
  std::array<bool, devices::kMaxStationDevices> model_pending_{};
  std::array<devices::ForceModel, devices::kMaxStationDevices> pending_models_{};
  std::size_t next_model_device_ = 0;
  std::array<std::uint8_t, devices::kForceModelFrameSize> model_frame_{};
  std::uint32_t send_sequence_ = 0;
  std::int64_t station_id_ = 0;
  std::atomic<bool> closing_ = false;
  std::int64_t states_received_ = 0;
  std::uint32_t last_sequence_ = 0;
  std::uint64_t window_states_ = 0;       // since the last link report
  std::uint64_t window_states_lost_ = 0;  // gaps in the agent's sequence numbers
};

}  // namespace incise::server
