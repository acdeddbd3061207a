#pragma once
// One connection to the server's /agent WebSocket, from resolve to close: hello, welcome, then
// the network half of the haptic bridge. It drains the device states the haptic loop queues in
// the HapticChannel every kDrainPeriod and sends them as DeviceState frames, one write in
// flight; it decodes the server's ForceModel frames and publishes each to the haptic loop, and
// logs session notices. A malformed message from the server closes the link with 1007 and the
// decoder's reason. The Agent makes a new StationLink per attempt and decides what to do when
// one ends.
//
// All work runs on the io_context's single thread (the channel's only consumer of states and
// only publisher of models); stop() may be called from any thread.

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

#include "devices/agent/haptic_channel.h"
#include "devices/agent/histogram.h"
#include "devices/agent/options.h"
#include "devices/protocol.h"
#include "transport/maybe_tls_stream.h"

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
  // For wss://: the context that verifies the server (transport::make_client_tls); null: ws://.
  std::shared_ptr<asio::ssl::context> tls;
  Hello hello;
  Clock::time_point epoch;  // t = 0 of device polls and frame timestamps
  std::size_t device_count = 1;
  // Called (io thread) with every state the haptic loop queued, sent or held back by the
  // deadband: the agent's full-rate local recording (--record-states). May be empty.
  std::function<void(const TimedState&)> recorder;
};

// How often the link looks for queued device states when no write is in flight. The haptic loop
// queues one every 1..4 ms; a finished write sends the next queued state at once. 1 ms: a state
// waits half a millisecond on average before it leaves.
inline constexpr Clock::duration kDrainPeriod = std::chrono::milliseconds(1);
// How often the agent reports the link to the server (protocol.h, LinkReport).
inline constexpr Clock::duration kReportPeriod = std::chrono::seconds(1);

// The link over one report period; io thread only.
inline constexpr std::size_t kWindowRoundTrips = 2048;
struct LinkWindow {
  uint64_t states_sent = 0;
  uint64_t states_held = 0;
  uint64_t models_received = 0;
  uint64_t models_lost = 0;
  std::array<uint64_t, kWindowRoundTrips> round_trip_us{};  // the first ones of the window
  std::size_t round_trips = 0;

  void add_round_trip(uint64_t us) {
    if (round_trips < round_trip_us.size()) round_trip_us[round_trips] = us;
    ++round_trips;
  }
  // Nearest-rank percentile of the window's round trips [us]; 0 when empty.
  double round_trip_percentile(double p) const;
};

// Totals over all links of an agent; io thread only.
struct BridgeStats {
  uint64_t states_sent = 0;
  uint64_t models_received = 0;
  uint64_t models_lost = 0;  // gaps in the server's sequence numbers
  LinkReport last_report;    // the last one sent
  // now - state_timestamp_us of every model that echoes a state this agent sent [us]: 10 us bins
  // up to 100 ms.
  Histogram round_trip_us{10, 10000};
};

class StationLink : public std::enable_shared_from_this<StationLink> {
 public:
  using WelcomeHandler = std::function<void(const Welcome&)>;
  using EndHandler = std::function<void(const LinkEnd&)>;

  // channel, stats and the handlers must outlive the link. on_end is called exactly once.
  StationLink(asio::io_context& io, const LinkSettings& settings, HapticChannel& channel,
              BridgeStats& stats, WelcomeHandler on_welcome, EndHandler on_end);

  void run();
  // Closes with 1000 (normal) if connected, else abandons the attempt; on_end reports Stopped.
  void stop();

 private:
  void do_resolve();
  void on_resolve(beast::error_code ec, asio::ip::tcp::resolver::results_type results);
  void on_connect(beast::error_code ec, asio::ip::tcp::endpoint endpoint);
  void on_tls(beast::error_code ec, asio::ip::tcp::endpoint endpoint);
  void on_handshake(beast::error_code ec);
  void on_hello_sent(beast::error_code ec, std::size_t bytes);
  void on_welcome(beast::error_code ec, std::size_t bytes);
  void on_welcome_timeout(beast::error_code ec);
  void do_drain();
  void on_drain(beast::error_code ec);
  void do_send();
  void on_sent(beast::error_code ec, std::size_t bytes);
  void do_read();
  void on_read(beast::error_code ec, std::size_t bytes);
  void on_force_model(const ForceModel& model);
  void send_report();
  void on_report_sent(beast::error_code ec, std::size_t bytes);
  void on_session_notice(const SessionNotice& notice);
  // Publishes each device's workspace mapping to the haptic loop (JSON "" = the default).
  void apply_calibration(const std::string& json_text);
  // Closes with 1007 (invalid payload) and reason; the link ends as Dropped.
  void reject(std::string_view reason);
  void do_stop();
  void do_close();
  void on_close(beast::error_code ec);
  bool sent_recently(uint64_t timestamp_us) const;

  void fail(beast::error_code ec, const char* what);
  void finish(LinkEnd::Kind kind, std::string reason);

  LinkSettings settings_;
  HapticChannel& channel_;
  BridgeStats& stats_;
  WelcomeHandler on_welcome_;
  EndHandler on_end_;

  asio::ip::tcp::resolver resolver_;
  websocket::stream<transport::MaybeTlsStream> ws_;
  websocket::response_type upgrade_response_;
  beast::flat_buffer read_buffer_;
  asio::steady_timer welcome_timer_;
  asio::steady_timer drain_timer_;
  std::string hello_text_;
  std::array<uint8_t, kDeviceStateFrameSize> frame_{};  // the one buffer every frame reuses
  // Timestamps of the last states sent, oldest overwritten first, to recognise a model's echo.
  std::array<uint64_t, 1024> sent_timestamps_{};
  std::string reject_reason_;  // set once a bad message made us close with 1007

  bool ws_open_ = false;
  bool welcomed_ = false;
  bool welcome_timed_out_ = false;
  bool write_in_flight_ = false;
  bool stopping_ = false;
  bool closing_ = false;
  bool rejecting_ = false;
  bool finished_ = false;
  uint32_t sequence_ = 0;
  uint32_t last_model_sequence_ = 0;
  std::array<uint64_t, kMaxDevices> last_answered_{};  // state timestamps, per device
  uint64_t models_seen_ = 0;
  LinkWindow window_;
  bool report_due_ = false;
  Clock::time_point window_start_{};  // of the report window, for the loop rate
  uint64_t window_start_ticks_ = 0;
  Clock::time_point next_report_;
  std::string report_text_;
  uint64_t messages_sent_ = 0;
  Clock::time_point next_drain_;
  Clock::time_point welcomed_at_;
};

}  // namespace incise::devices::agent
