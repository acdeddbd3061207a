#include "devices/agent/station_link.h"

#include <boost/asio/dispatch.hpp>
#include <boost/asio/strand.hpp>
#include <boost/beast/http.hpp>

namespace incise::devices::agent {
namespace {

namespace http = beast::http;

// Generous for a LAN or a loaded server, short enough that an attempt never hangs.
constexpr auto kConnectTimeout = std::chrono::seconds(5);
constexpr auto kHandshakeTimeout = std::chrono::seconds(5);
constexpr auto kWelcomeTimeout = std::chrono::seconds(5);
// Without traffic from the server for this long (it answers our pings) the link is dead.
constexpr auto kIdleTimeout = std::chrono::seconds(10);
// Stopping must finish within ~200 ms even if the server never answers our close.
constexpr auto kCloseTimeout = std::chrono::milliseconds(150);

std::string describe(const websocket::close_reason& reason) {
  std::string text = std::to_string(reason.code);
  if (!reason.reason.empty()) {
    text += " \"" + std::string(reason.reason.data(), reason.reason.size()) + "\"";
  }
  return text;
}

}  // namespace

StationLink::StationLink(asio::io_context& io, const LinkSettings& settings, Device& device,
                         WelcomeHandler on_welcome, EndHandler on_end)
    : settings_(settings),
      device_(device),
      on_welcome_(std::move(on_welcome)),
      on_end_(std::move(on_end)),
      resolver_(asio::make_strand(io)),
      ws_(resolver_.get_executor()),
      welcome_timer_(resolver_.get_executor()),
      tick_timer_(resolver_.get_executor()),
      hello_text_(build_hello(settings.hello)) {}

void StationLink::run() {
  asio::dispatch(ws_.get_executor(),
                 beast::bind_front_handler(&StationLink::do_resolve, shared_from_this()));
}

void StationLink::stop() {
  asio::dispatch(ws_.get_executor(),
                 beast::bind_front_handler(&StationLink::do_stop, shared_from_this()));
}

void StationLink::do_resolve() {
  if (stopping_) return finish(LinkEnd::Kind::Stopped, "");
  resolver_.async_resolve(settings_.server.host, settings_.server.port,
                          beast::bind_front_handler(&StationLink::on_resolve, shared_from_this()));
}

void StationLink::on_resolve(beast::error_code ec, asio::ip::tcp::resolver::results_type results) {
  if (ec) return fail(ec, "resolve");
  beast::get_lowest_layer(ws_).expires_after(kConnectTimeout);
  beast::get_lowest_layer(ws_).async_connect(
      results, beast::bind_front_handler(&StationLink::on_connect, shared_from_this()));
}

void StationLink::on_connect(beast::error_code ec, asio::ip::tcp::endpoint endpoint) {
  if (ec) return fail(ec, "connect");
  // The websocket stream keeps its own timeouts from here on.
  beast::get_lowest_layer(ws_).expires_never();
  websocket::stream_base::timeout timeouts;
  timeouts.handshake_timeout = kHandshakeTimeout;
  timeouts.idle_timeout = kIdleTimeout;
  timeouts.keep_alive_pings = true;
  ws_.set_option(timeouts);
  ws_.set_option(websocket::stream_base::decorator(
      [agent = settings_.hello.agent](websocket::request_type& request) {
        request.set(http::field::user_agent, agent);
      }));
  ws_.read_message_max(kMaxMessageSize);
  // The Host header names the port we actually reached.
  const std::string host = settings_.server.host + ":" + std::to_string(endpoint.port());
  ws_.async_handshake(upgrade_response_, host, settings_.server.target,
                      beast::bind_front_handler(&StationLink::on_handshake, shared_from_this()));
}

void StationLink::on_handshake(beast::error_code ec) {
  if (ec == websocket::error::upgrade_declined && !stopping_) {
    const auto status = upgrade_response_.result();
    const std::string reason = "server declined the WebSocket upgrade: HTTP " +
                               std::to_string(upgrade_response_.result_int()) + " " +
                               std::string(upgrade_response_.reason());
    const bool refused = status == http::status::unauthorized || status == http::status::forbidden;
    return finish(refused ? LinkEnd::Kind::Refused : LinkEnd::Kind::Failed, reason);
  }
  if (ec) return fail(ec, "handshake");
  ws_open_ = true;
  if (stopping_) return do_close();
  ws_.text(true);
  write_in_flight_ = true;
  ws_.async_write(asio::buffer(hello_text_),
                  beast::bind_front_handler(&StationLink::on_hello_sent, shared_from_this()));
}

void StationLink::on_hello_sent(beast::error_code ec, std::size_t) {
  write_in_flight_ = false;
  if (ec) return fail(ec, "send hello");
  if (stopping_) return do_close();
  welcome_timer_.expires_after(kWelcomeTimeout);
  welcome_timer_.async_wait(
      beast::bind_front_handler(&StationLink::on_welcome_timeout, shared_from_this()));
  ws_.async_read(read_buffer_,
                 beast::bind_front_handler(&StationLink::on_welcome, shared_from_this()));
}

void StationLink::on_welcome_timeout(beast::error_code ec) {
  if (ec || welcomed_ || finished_) return;  // cancelled: the welcome (or an error) came first
  welcome_timed_out_ = true;
  beast::get_lowest_layer(ws_).cancel();
}

void StationLink::on_welcome(beast::error_code ec, std::size_t) {
  welcome_timer_.cancel();
  if (welcome_timed_out_ && !stopping_) {
    return finish(LinkEnd::Kind::Failed, "no welcome from the server within " +
                                             std::to_string(kWelcomeTimeout.count()) + " s");
  }
  if (ec) return fail(ec, "read welcome");
  if (stopping_) return do_close();
  if (!ws_.got_text()) return finish(LinkEnd::Kind::Failed, "expected a welcome, got binary");
  const auto welcome = parse_welcome(beast::buffers_to_string(read_buffer_.data()));
  read_buffer_.consume(read_buffer_.size());
  if (!welcome) return finish(LinkEnd::Kind::Failed, welcome.error);

  welcomed_ = true;
  welcomed_at_ = Clock::now();
  on_welcome_(*welcome.value);
  ws_.binary(true);
  next_send_ = welcomed_at_;
  do_read();
  do_tick();
}

void StationLink::do_tick() {
  // An absolute deadline, like sleep_until: the rate does not drift with handler latency.
  tick_timer_.expires_at(next_send_);
  tick_timer_.async_wait(beast::bind_front_handler(&StationLink::on_tick, shared_from_this()));
}

void StationLink::on_tick(beast::error_code ec) {
  if (ec || stopping_ || finished_) return;
  // With the previous frame still in flight (a congested link) this sample is dropped: the
  // server wants the latest state, not a queue of old ones.
  if (!write_in_flight_) do_send();
  next_send_ += settings_.send_period;
  // After a stall (suspend, overload) resume from now instead of bursting to catch up.
  if (const auto now = Clock::now(); next_send_ < now) next_send_ = now + settings_.send_period;
  do_tick();
}

void StationLink::do_send() {
  const Clock::duration since_epoch = Clock::now() - settings_.epoch;
  const DeviceState state = device_.poll(std::chrono::duration<double>(since_epoch).count());
  const auto t_us = std::chrono::duration_cast<std::chrono::microseconds>(since_epoch).count();
  const std::size_t size = encode(state, sequence_, static_cast<uint64_t>(t_us), frame_);
  ++sequence_;
  write_in_flight_ = true;
  ws_.async_write(asio::buffer(frame_.data(), size),
                  beast::bind_front_handler(&StationLink::on_sent, shared_from_this()));
}

void StationLink::on_sent(beast::error_code ec, std::size_t) {
  write_in_flight_ = false;
  if (ec) return fail(ec, "send device state");
  ++messages_sent_;
  if (stopping_) do_close();
}

void StationLink::do_read() {
  ws_.async_read(read_buffer_,
                 beast::bind_front_handler(&StationLink::on_read, shared_from_this()));
}

void StationLink::on_read(beast::error_code ec, std::size_t) {
  if (ec) return fail(ec, "read");
  // Protocol 1 has no server -> agent messages after welcome; newer servers' (force models) are
  // skipped until this agent learns them.
  read_buffer_.consume(read_buffer_.size());
  do_read();
}

void StationLink::do_stop() {
  if (stopping_ || finished_) return;
  stopping_ = true;
  welcome_timer_.cancel();
  tick_timer_.cancel();
  if (!ws_open_) {
    // Resolving, connecting or upgrading: abandon; the pending handler reports Stopped.
    resolver_.cancel();
    beast::get_lowest_layer(ws_).cancel();
    return;
  }
  // Only one write may be in flight; on_sent / on_hello_sent close after it.
  if (!write_in_flight_) do_close();
}

void StationLink::do_close() {
  if (closing_ || finished_) return;
  closing_ = true;
  websocket::stream_base::timeout timeouts;
  timeouts.handshake_timeout = kCloseTimeout;
  timeouts.idle_timeout = websocket::stream_base::none();
  timeouts.keep_alive_pings = false;
  ws_.set_option(timeouts);
  ws_.async_close(websocket::close_code::normal,
                  beast::bind_front_handler(&StationLink::on_close, shared_from_this()));
}

void StationLink::on_close(beast::error_code ec) {
  finish(LinkEnd::Kind::Stopped, ec ? "close: " + ec.message() : "");
}

void StationLink::fail(beast::error_code ec, const char* what) {
  if (finished_) return;
  if (stopping_) {
    // Errors from operations that stop() cut short. A pending read that sees our close
    // completing is not the end yet: on_close reports it.
    if (closing_) return;
    return finish(LinkEnd::Kind::Stopped, "");
  }
  const LinkEnd::Kind lost = welcomed_ ? LinkEnd::Kind::Dropped : LinkEnd::Kind::Failed;
  if (ec == websocket::error::closed) {
    const websocket::close_reason& reason = ws_.reason();
    if (reason.code == websocket::close_code::policy_error) {
      return finish(LinkEnd::Kind::Refused,
                    std::string(reason.reason.data(), reason.reason.size()));
    }
    return finish(lost, "server closed the connection (" + describe(reason) + ")");
  }
  finish(lost, std::string(what) + ": " + ec.message());
}

void StationLink::finish(LinkEnd::Kind kind, std::string reason) {
  if (finished_) return;
  finished_ = true;
  welcome_timer_.cancel();
  tick_timer_.cancel();
  // Abort whatever is still pending (a read after a failed write); after a clean close the
  // socket is already shut and this is a no-op.
  beast::error_code ignored;
  beast::get_lowest_layer(ws_).socket().close(ignored);
  LinkEnd end;
  end.kind = kind;
  end.reason = std::move(reason);
  end.messages_sent = messages_sent_;
  if (welcomed_) end.connected_for = Clock::now() - welcomed_at_;
  on_end_(end);
}

}  // namespace incise::devices::agent
