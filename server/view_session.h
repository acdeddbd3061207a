#pragma once
// A viewer's WebSocket onto a live session or a replay (docs/api.md, "View WebSocket"): JPEG
// frames as binary messages, metrics as JSON about ten times a second, control messages from the
// viewer. Memory stays bounded whatever the viewer does: one write in flight, one pending frame
// slot that the newest frame replaces, one pending metrics slot, and no frames at all once two
// are unacknowledged.
#include <atomic>
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "server/app_state.h"
#include "server/live/frame_streamer.h"
#include "server/live/live_session.h"
#include "server/live/replay_session.h"
#include "server/view_message.h"
#include "transport/maybe_tls_stream.h"

namespace incise::server {

// What a viewer asked for in the upgrade's query (clamped to the documented limits).
struct ViewRequest {
  int fps = 30;
  int width = 640;
  int height = 480;
  bool outside = false;  // view=outside: the camera outside the body
};
ViewRequest parse_view_query(std::string_view target);

class ViewSession : public std::enable_shared_from_this<ViewSession> {
 public:
  static constexpr int kMaxFramesInFlight = 2;
  static constexpr std::size_t kMaxClientMessage = 1024;

  // Watches a live session. outside_view_allowed: whether the viewer may ask for the outside view
  // (api::may_look_outside); a request for it otherwise closes with 1008.
  ViewSession(transport::MaybeTlsStream&& stream, std::shared_ptr<live::LiveSession> session,
              bool outside_view_allowed);
  // Owns and drives a replay.
  ViewSession(transport::MaybeTlsStream&& stream, std::unique_ptr<live::ReplaySession> replay,
              bool outside_view_allowed);

  ~ViewSession();

  void run(boost::beast::http::request<boost::beast::http::string_body> upgrade);
  // Thread-safe: closes the view with `code` and `reason` (AppState::close_views_of).
  void close(boost::beast::websocket::close_code code, std::string reason);
  // Keeps `resource` (a replay's slot) until this view has closed and its replay is gone.
  void hold(std::shared_ptr<void> resource) { held_ = std::move(resource); }

 private:
  // One of live or replay.
  ViewSession(transport::MaybeTlsStream&& stream, std::shared_ptr<live::LiveSession> live,
              std::unique_ptr<live::ReplaySession> replay, bool outside_view_allowed);
  class Sink;
  live::StreamSource& source() const;
  live::FrameStreamer& streamer() const;

  void on_accept(boost::beast::error_code ec);
  void do_read();
  void on_read(boost::beast::error_code ec, std::size_t bytes);
  // A viewer's message, parsed and allowed (on_read closes the socket otherwise).
  void apply(const ViewMessage& message);
  void on_frame(std::shared_ptr<const std::vector<std::uint8_t>> message,
                std::chrono::steady_clock::time_point published_at);
  void schedule_metrics();
  void send_metrics();
  void do_write();
  void on_write(boost::beast::error_code ec, std::size_t bytes);
  void do_close(boost::beast::websocket::close_code code, std::string reason);

  boost::beast::websocket::stream<transport::MaybeTlsStream> ws_;
  boost::asio::steady_timer metrics_timer_;
  boost::beast::flat_buffer buffer_;
  std::shared_ptr<live::LiveSession> live_;
  std::unique_ptr<live::ReplaySession> replay_;
  std::shared_ptr<void> held_;  // released after replay_ (the destructor resets that first)
  std::shared_ptr<Sink> sink_;
  bool outside_view_allowed_ = false;

  bool writing_ = false;
  bool closing_ = false;
  bool ended_sent_ = false;
  std::optional<std::string> pending_text_;
  std::optional<std::string> end_notice_;  // {"type": "ended"}, then a normal close
  bool end_in_flight_ = false;
  std::string text_in_flight_;
  std::shared_ptr<const std::vector<std::uint8_t>> pending_frame_;
  std::chrono::steady_clock::time_point pending_published_at_;
  std::shared_ptr<const std::vector<std::uint8_t>> frame_in_flight_;
  std::int64_t frames_sent_ = 0;
};

}  // namespace incise::server
