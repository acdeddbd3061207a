#include "devices/agent/station_link.h"

#include <boost/asio/dispatch.hpp>
#include <boost/asio/strand.hpp>
#include <boost/beast/http.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "devices/agent/force_guard.h"
#include "devices/agent/log.h"
#include "devices/station_calibration.h"
#include "devices/station_calibration_json.h"

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

double LinkWindow::round_trip_percentile(double p) const {
  const std::size_t n = std::min<std::size_t>(round_trips, round_trip_us.size());
  if (n == 0) return 0.0;
  std::array<uint64_t, kWindowRoundTrips> sorted;
  std::copy_n(round_trip_us.begin(), n, sorted.begin());
  const std::size_t rank =
      std::min(n - 1, static_cast<std::size_t>(std::ceil(p / 100.0 * static_cast<double>(n))) -
                          (p > 0 ? 1 : 0));
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(rank),
                   sorted.begin() + static_cast<std::ptrdiff_t>(n));
  return static_cast<double>(sorted[rank]);
}

StationLink::StationLink(asio::io_context& io, const LinkSettings& settings, HapticChannel& channel,
                         BridgeStats& stats, WelcomeHandler on_welcome, EndHandler on_end)
    : settings_(settings),
      channel_(channel),
      stats_(stats),
      on_welcome_(std::move(on_welcome)),
      on_end_(std::move(on_end)),
      resolver_(asio::make_strand(io)),
      ws_(transport::make_stream(beast::tcp_stream(resolver_.get_executor()), settings.tls.get())),
      welcome_timer_(resolver_.get_executor()),
      drain_timer_(resolver_.get_executor()),
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
  ws_.next_layer().tcp().expires_after(kConnectTimeout);
  ws_.next_layer().tcp().async_connect(
      results, beast::bind_front_handler(&StationLink::on_connect, shared_from_this()));
}

void StationLink::on_connect(beast::error_code ec, asio::ip::tcp::endpoint endpoint) {
  if (ec) return fail(ec, "connect");
  // wss://: the TLS handshake first, under the connect deadline (nothing on ws://).
  if (!ws_.next_layer().expect_server(settings_.server.host)) {
    return finish(LinkEnd::Kind::Failed, "TLS: cannot name the server " + settings_.server.host);
  }
  ws_.next_layer().async_handshake(
      asio::ssl::stream_base::client,
      [self = shared_from_this(), endpoint](beast::error_code ec) { self->on_tls(ec, endpoint); });
}

void StationLink::on_tls(beast::error_code ec, asio::ip::tcp::endpoint endpoint) {
  if (ec) return fail(ec, "TLS handshake");
  // The websocket stream keeps its own timeouts from here on.
  ws_.next_layer().tcp().expires_never();
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
  ws_.next_layer().tcp().cancel();
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
  apply_calibration(welcome.value->calibration);
  on_welcome_(*welcome.value);
  ws_.binary(true);
  // States queued while no link was up (at most a few, from the end of the previous link) are
  // stale; from now on the haptic loop queues them for this link.
  TimedState stale;
  while (channel_.states.pop(stale)) {
  }
  channel_.link_up.store(true, std::memory_order_release);
  next_drain_ = welcomed_at_;
  next_report_ = welcomed_at_ + kReportPeriod;
  window_start_ = welcomed_at_;
  window_start_ticks_ = channel_.loop_ticks.load(std::memory_order_relaxed);
  do_read();
  do_drain();
}

void StationLink::do_drain() {
  // An absolute deadline, like sleep_until: the period does not drift with handler latency.
  drain_timer_.expires_at(next_drain_);
  drain_timer_.async_wait(beast::bind_front_handler(&StationLink::on_drain, shared_from_this()));
}

void StationLink::on_drain(beast::error_code ec) {
  if (ec || stopping_ || rejecting_ || finished_) return;
  const Clock::time_point now = Clock::now();
  if (now >= next_report_) {
    report_due_ = true;
    next_report_ = now + kReportPeriod;
  }
  if (!write_in_flight_) do_send();
  next_drain_ += kDrainPeriod;
  // After a stall (suspend, overload) resume from now instead of firing back to back.
  if (const auto now = Clock::now(); next_drain_ < now) next_drain_ = now + kDrainPeriod;
  do_drain();
}

void StationLink::do_send() {
  if (report_due_) return send_report();
  TimedState queued;
  // States the deadband held back are only recorded (locally, if asked); the next one to send
  // goes out.
  for (;;) {
    if (!channel_.states.pop(queued)) return;
    if (settings_.recorder) settings_.recorder(queued);
    if (queued.send) break;
    ++window_.states_held;
  }
  ++window_.states_sent;
  const std::size_t size = encode(queued.state, sequence_, queued.timestamp_us, frame_);
  sent_timestamps_[sequence_ % sent_timestamps_.size()] = queued.timestamp_us;
  ++sequence_;
  write_in_flight_ = true;
  ws_.binary(true);
  ws_.async_write(asio::buffer(frame_.data(), size),
                  beast::bind_front_handler(&StationLink::on_sent, shared_from_this()));
}

void StationLink::send_report() {
  report_due_ = false;
  LinkReport report;
  report.rtt_p50_ms = window_.round_trip_percentile(50) * 1e-3;
  report.rtt_p99_ms = window_.round_trip_percentile(99) * 1e-3;
  const uint64_t expected = window_.models_received + window_.models_lost;
  report.loss_down = expected == 0
                         ? 0.0
                         : static_cast<double>(window_.models_lost) / static_cast<double>(expected);
  const Clock::time_point now = Clock::now();
  const uint64_t ticks = channel_.loop_ticks.load(std::memory_order_relaxed);
  const double window_s = std::chrono::duration<double>(now - window_start_).count();
  if (window_s > 0) {
    report.loop_hz = static_cast<double>(ticks - window_start_ticks_) / window_s;
  }
  window_start_ = now;
  window_start_ticks_ = ticks;
  report.states_sent = window_.states_sent;
  report.states_held = window_.states_held;
  for (std::size_t i = 0; i < settings_.device_count; ++i) {
    const DeviceTelemetry& t = channel_.telemetry[i];
    DeviceLinkReport device;
    device.index = static_cast<int>(i);
    device.model_age_ms = t.model_age_us.load(std::memory_order_relaxed) * 1e-3;
    device.fault = to_string(static_cast<GuardFault>(t.fault.load(std::memory_order_relaxed)));
    device.force_n = t.force_n.load(std::memory_order_relaxed);
    device.damping_ns_m = t.damping.load(std::memory_order_relaxed);
    device.dissipated_j = t.dissipated_j.load(std::memory_order_relaxed);
    report.devices.push_back(std::move(device));
  }
  stats_.last_report = report;
  window_ = {};
  report_text_ = build_link_report(report);
  write_in_flight_ = true;
  ws_.text(true);
  ws_.async_write(asio::buffer(report_text_),
                  beast::bind_front_handler(&StationLink::on_report_sent, shared_from_this()));
}

void StationLink::on_report_sent(beast::error_code ec, std::size_t) {
  write_in_flight_ = false;
  if (ec) return fail(ec, "send link report");
  if (stopping_ || rejecting_) return do_close();
  do_send();
}

void StationLink::on_sent(beast::error_code ec, std::size_t) {
  write_in_flight_ = false;
  if (ec) return fail(ec, "send device state");
  ++messages_sent_;
  ++stats_.states_sent;
  if (stopping_ || rejecting_) return do_close();
  // The next queued state goes at once: with a backlog (a slow write) the link catches up at
  // the speed of the network instead of one state per drain period.
  do_send();
}

void StationLink::do_read() {
  ws_.async_read(read_buffer_,
                 beast::bind_front_handler(&StationLink::on_read, shared_from_this()));
}

void StationLink::on_read(beast::error_code ec, std::size_t) {
  if (ec) return fail(ec, "read");
  if (stopping_ || rejecting_) return;
  const auto bytes = read_buffer_.cdata();
  const bool text = ws_.got_text();
  if (text) {
    const std::string body(static_cast<const char*>(bytes.data()), bytes.size());
    read_buffer_.consume(read_buffer_.size());
    if (message_type(body) == "calibration") {
      const auto calibration = parse_calibration_notice(body);
      if (!calibration) return reject(calibration.error);
      apply_calibration(*calibration.value);
      return do_read();
    }
    const auto notice = parse_session_notice(body);
    if (!notice) return reject(notice.error);
    on_session_notice(*notice.value);
  } else {
    const ForceModelDecodeResult result = decode_force_model(
        std::span<const uint8_t>(static_cast<const uint8_t*>(bytes.data()), bytes.size()));
    read_buffer_.consume(read_buffer_.size());
    if (!result) return reject(result.reason());
    // The server numbers its frames: a gap is force models lost on the way (TCP loses nothing,
    // but a proxy or a lossy transport may).
    const uint32_t sequence = result.message().header.sequence;
    if (models_seen_ > 0 && sequence - last_model_sequence_ > 1 &&
        sequence - last_model_sequence_ < 0x80000000u) {
      const uint32_t lost = sequence - last_model_sequence_ - 1;
      window_.models_lost += lost;
      stats_.models_lost += lost;
    }
    last_model_sequence_ = sequence;
    ++models_seen_;
    ++window_.models_received;
    on_force_model(result.message().model);
  }
  do_read();
}

void StationLink::on_force_model(const ForceModel& model) {
  const Clock::time_point now = Clock::now();
  // A model for a device this station does not have is ignored (the server's task binds tools
  // to the devices it expects).
  if (model.device_index < settings_.device_count)
    channel_.models[model.device_index].publish({model, now});
  ++stats_.models_received;
  // A round trip is the first answer to a state: while the deadband holds the hand's state back,
  // the server keeps answering the last one sent, and those answers are not later round trips.
  const bool first_answer = model.device_index < last_answered_.size() &&
                            model.state_timestamp_us != last_answered_[model.device_index];
  if (first_answer) last_answered_[model.device_index] = model.state_timestamp_us;
  if (first_answer && sent_recently(model.state_timestamp_us)) {
    const auto now_us =
        std::chrono::duration_cast<std::chrono::microseconds>(now - settings_.epoch).count();
    const uint64_t round_trip = static_cast<uint64_t>(now_us) - model.state_timestamp_us;
    stats_.round_trip_us.add(round_trip);
    window_.add_round_trip(round_trip);
    channel_.telemetry[model.device_index].round_trip_us.store(
        static_cast<uint32_t>(std::min<uint64_t>(round_trip, UINT32_MAX)),
        std::memory_order_relaxed);
  }
}

bool StationLink::sent_recently(uint64_t timestamp_us) const {
  // Newest first: the server echoes a recent state, and timestamps only grow, so the search
  // stops at the first older one.
  const uint64_t kept = std::min<uint64_t>(sequence_, sent_timestamps_.size());
  for (uint64_t back = 1; back <= kept; ++back) {
    const uint64_t sent = sent_timestamps_[(sequence_ - back) % sent_timestamps_.size()];
    if (sent == timestamp_us) return true;
    if (sent < timestamp_us) return false;
  }
  return false;
}

void StationLink::apply_calibration(const std::string& json_text) {
  const auto parsed = json_text.empty()
                          ? ParseResult<StationCalibration>::success(default_station_calibration())
                          : parse_station_calibration(json_text);
  if (!parsed) {
    // The server validates what it stores, so this is a corrupt or newer message: keep the
    // mapping in force rather than guess.
    log_line("calibration from the server refused, keeping the current one: " + parsed.error);
    return;
  }
  for (std::size_t i = 0; i < settings_.device_count; ++i) {
    const DeviceCalibration* device = parsed.value->find(static_cast<int>(i));
    channel_.mappings[i].publish(device ? device->mapping : WorkspaceMapping{});
  }
  if (!json_text.empty())
    log_line("calibration applied: " + station_calibration_json(*parsed.value));
}

void StationLink::on_session_notice(const SessionNotice& notice) {
  log_line(notice.session_id == 0
               ? "no session (" + notice.state + ")"
               : "session " + std::to_string(notice.session_id) + " " + notice.state);
}

void StationLink::reject(std::string_view reason) {
  rejecting_ = true;
  reject_reason_ = std::string(reason);
  channel_.link_up.store(false, std::memory_order_release);
  drain_timer_.cancel();
  // Only one write may be in flight; on_sent closes after it.
  if (!write_in_flight_) do_close();
}

void StationLink::do_stop() {
  if (stopping_ || finished_) return;
  stopping_ = true;
  channel_.link_up.store(false, std::memory_order_release);
  welcome_timer_.cancel();
  drain_timer_.cancel();
  if (!ws_open_) {
    // Resolving, connecting or upgrading: abandon; the pending handler reports Stopped.
    resolver_.cancel();
    ws_.next_layer().tcp().cancel();
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
  const bool invalid = rejecting_ && !stopping_;
  const websocket::close_reason reason =
      invalid ? websocket::close_reason(websocket::close_code::bad_payload, reject_reason_)
              : websocket::close_reason(websocket::close_code::normal);
  ws_.async_close(reason, beast::bind_front_handler(&StationLink::on_close, shared_from_this()));
}

void StationLink::on_close(beast::error_code ec) {
  if (rejecting_ && !stopping_) {
    return finish(LinkEnd::Kind::Dropped,
                  "bad message from the server, closed with 1007: " + reject_reason_);
  }
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
  if (rejecting_) {
    if (closing_) return;  // likewise, on_close reports the end
    return finish(LinkEnd::Kind::Dropped,
                  "bad message from the server, closed with 1007: " + reject_reason_);
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
  channel_.link_up.store(false, std::memory_order_release);
  // The next link measures its own round trip.
  for (DeviceTelemetry& t : channel_.telemetry)
    t.round_trip_us.store(0, std::memory_order_relaxed);
  welcome_timer_.cancel();
  drain_timer_.cancel();
  // Abort whatever is still pending (a read after a failed write); after a clean close the
  // socket is already shut and this is a no-op.
  beast::error_code ignored;
  ws_.next_layer().tcp().socket().close(ignored);
  LinkEnd end;
  end.kind = kind;
  end.reason = std::move(reason);
  end.messages_sent = messages_sent_;
  if (welcomed_) end.connected_for = Clock::now() - welcomed_at_;
  on_end_(end);
}

}  // namespace incise::devices::agent
