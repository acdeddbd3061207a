#include "server/agent_session.h"

#include <chrono>
#include <iostream>
#include <mutex>

#include <nlohmann/json.hpp>

#include "db/stations_repo.h"
#include "devices/protocol.h"
#include "devices/station_calibration_json.h"
#include "server/demo_data.h"
#include "server/server_options.h"
#include "server/wire_text.h"

namespace incise::server {

namespace beast = boost::beast;
namespace websocket = beast::websocket;
namespace net = boost::asio;

namespace {
constexpr std::size_t kBeastReadLimit = 64 * 1024;
constexpr auto kAgentIdleTimeout = std::chrono::seconds(3);
// The wrong-token limiter counts per address only (one "account" for all stations).
constexpr std::string_view kAgentAccount = "station-token";

std::uint64_t monotonic_us() {
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(
                                        std::chrono::steady_clock::now().time_since_epoch())
                                        .count());
}
}  // namespace

AgentSession::AgentSession(transport::MaybeTlsStream&& stream, std::shared_ptr<AppState> app)
    : ws_(std::move(stream)), app_(std::move(app)), hello_timer_(ws_.get_executor()) {
  beast::error_code ec;
  const auto remote = ws_.next_layer().tcp().socket().remote_endpoint(ec);
  address_ = ec ? "unknown" : remote.address().to_string();
}

AgentSession::~AgentSession() {
  if (station_id_ != 0) {
    app_->agent_left(this);
    app_->unlink_station_if_gone(station_id_);
    std::cerr << "incise-server: station " << station_id_ << " agent disconnected\n";
  }
}

void AgentSession::run(beast::http::request<beast::http::string_body> upgrade) {
  address_ = request_client(address_, upgrade["X-Forwarded-For"], app_->config().trusted_proxy);
  // Agents stream hundreds of states a second, so a few seconds of silence means the station is
  // gone (a crashed machine or a pulled cable sends no FIN): close, so that its session pauses
  // now and not after Beast's default five minutes.
  websocket::stream_base::timeout timeouts{};
  timeouts.handshake_timeout = std::chrono::seconds(30);
  timeouts.idle_timeout = kAgentIdleTimeout;
  timeouts.keep_alive_pings = true;
  ws_.set_option(timeouts);
  // Beast's own limit closes with 1009 but no reason; a higher one lets on_read say why.
  ws_.read_message_max(kBeastReadLimit);
  ws_.async_accept(upgrade,
                   beast::bind_front_handler(&AgentSession::on_accept, shared_from_this()));
}

void AgentSession::on_accept(beast::error_code ec) {
  if (ec) return;
  // Keep-alive pings would hold a silent connection open for ever: the hello has a deadline.
  hello_timer_.expires_after(kHelloDeadline);
  hello_timer_.async_wait(
      beast::bind_front_handler(&AgentSession::on_hello_deadline, shared_from_this()));
  do_read();
}

void AgentSession::on_hello_deadline(beast::error_code ec) {
  if (ec || station_id_ != 0) return;  // cancelled by the hello, or it came
  do_close(websocket::close_code::policy_error,
           "no hello within " + std::to_string(kHelloDeadline.count()) + " s");
}

void AgentSession::do_read() {
  buffer_.clear();
  ws_.async_read(buffer_, beast::bind_front_handler(&AgentSession::on_read, shared_from_this()));
}

void AgentSession::on_read(beast::error_code ec, std::size_t bytes) {
  if (ec) {
    // Closed, timed out or reset: the destructor marks the station offline. A pending hello
    // deadline would hold this session for up to 5 s more.
    hello_timer_.cancel();
    return;
  }
  if (closing_) return;
  if (bytes > devices::kMaxMessageSize) {
    return do_close(websocket::close_code::too_big, "message of " + std::to_string(bytes) +
                                                        " bytes exceeds " +
                                                        std::to_string(devices::kMaxMessageSize));
  }
  if (station_id_ == 0) return handle_hello();
  if (ws_.got_text()) return handle_text();
  handle_device_state();
}

void AgentSession::handle_text() {
  const std::string text = beast::buffers_to_string(buffer_.data());
  buffer_.consume(buffer_.size());
  const std::string type = devices::message_type(text);
  if (type != "link") {
    return do_close(websocket::close_code::policy_error,
                    type.empty() ? "a text message must be a JSON object with a \"type\""
                                 : "text message of type \"" + type.substr(0, 40) +
                                       "\" is not part of protocol 1 (expected link)");
  }
  const auto report = devices::parse_link_report(text);
  if (!report) return do_close(websocket::close_code::bad_payload, report.error);
  // The agent's view of the link, plus what only the server sees: device states lost on the
  // way up (gaps in the agent's sequence numbers) since the previous report.
  const std::uint64_t expected = window_states_ + window_states_lost_;
  // Re-serialised from what was parsed: only the known fields reach the viewers.
  nlohmann::json link = nlohmann::json::parse(devices::build_link_report(*report.value));
  link.erase("type");
  link["loss_up"] = expected == 0
                        ? 0.0
                        : static_cast<double>(window_states_lost_) / static_cast<double>(expected);
  window_states_ = 0;
  window_states_lost_ = 0;
  if (app_->agent_for_station(station_id_).get() == this) {
    app_->live_sessions().on_link_report(station_id_, std::move(link));
  }
  do_read();
}

void AgentSession::handle_hello() {
  if (!ws_.got_text()) {
    return do_close(websocket::close_code::policy_error, "the first message must be the hello");
  }
  const auto hello = devices::parse_hello(beast::buffers_to_string(buffer_.data()));
  if (!hello) return do_close(websocket::close_code::policy_error, hello.error);

  auto& limiter = app_->agent_limiter();
  const auto now = app_->now();
  if (const auto wait = limiter.retry_after(kAgentAccount, address_, now); wait > 0) {
    // 1013: the agent retries later (a good token from a held address is held back too).
    return do_close(websocket::close_code::try_again_later, "too many wrong station tokens from " +
                                                                address_ + "; try again in " +
                                                                std::to_string(wait) + " s");
  }
  if (!app_->config().demo && is_demo_station_token(hello.value->station_token)) {
    // Demo stations exist only in a demo: their tokens are public (docs/security.md).
    limiter.record_failure(kAgentAccount, address_, now);
    return do_close(websocket::close_code::policy_error,
                    "demo station tokens are accepted only by a server started with --demo");
  }

  std::optional<db::Station> station;
  std::string calibration;
  {
    auto db = app_->pool().acquire();
    db::StationsRepo stations(*db);
    station = stations.find_by_token(hello.value->station_token);
    if (station) calibration = stations.calibration(station->id);
  }
  if (station && !calibration.empty() && !devices::parse_station_calibration(calibration)) {
    // Stored before a schema change, or edited by hand: the agent runs with identity mappings
    // rather than never connecting; the admin sees the error on GET .../calibration.
    std::cerr << "incise-server: station " << station->id
              << " has an invalid stored calibration; sending none: "
              << devices::parse_station_calibration(calibration).error << "\n";
    calibration.clear();
  }
  if (!station) {
    limiter.record_failure(kAgentAccount, address_, now);
    std::cerr << "incise-server: unknown station token from " << address_ << "\n";
    return do_close(websocket::close_code::policy_error, "unknown station token");
  }
  // No success clears the count: one valid token must not buy guesses at the others.
  if (station->retired()) {
    return do_close(websocket::close_code::policy_error,
                    "station " + station->name + " is retired; an admin can return it to service");
  }
  if (const auto holder = app_->agent_try_join(station->id, shared_from_this()); !holder.empty()) {
    // A stolen token must not take a running station over, nor two agents drive one hand. The
    // agent retries on 1013, so a reconnect goes through once the old link has gone.
    std::cerr << "incise-server: station " << station->id << ": second link from " << address_
              << " refused; the agent from " << holder << " holds it\n";
    return do_close(websocket::close_code::try_again_later,
                    "station " + station->name + " already has a connected agent (from " + holder +
                        "); try again once it has gone");
  }
  // Across nodes, the shared database says who holds the station (docs/scale_out.md).
  std::string other_node;
  try {
    other_node = app_->link_station_here(station->id);
  } catch (const std::exception& e) {
    other_node = "?";
    std::cerr << "incise-server: station " << station->id
              << ": cannot record its link: " << e.what() << "\n";
  }
  if (!other_node.empty()) {
    app_->agent_left(this);
    return do_close(websocket::close_code::try_again_later,
                    other_node == "?"
                        ? "the database cannot be reached; try again in a moment"
                        : "station " + station->name + " already has a connected agent (at node " +
                              other_node + "); try again once it has gone");
  }
  station_id_ = station->id;
  hello_timer_.cancel();
  std::cerr << "incise-server: station " << station->id << " (" << station->name
            << ") agent connected from " << address_ << ": " << hello.value->agent << "\n";
  texts_.push_back(devices::build_welcome({station->id, station->name, calibration}));
  do_write();
  do_read();
}

void AgentSession::send_force_model(const devices::ForceModel& model) {
  if (model.device_index >= devices::kMaxStationDevices) return;
  net::post(ws_.get_executor(), [self = shared_from_this(), model] {
    self->pending_models_[model.device_index] = model;
    self->model_pending_[model.device_index] = true;
    self->do_write();
  });
}

void AgentSession::send_text(std::string text) {
  net::post(ws_.get_executor(), [self = shared_from_this(), text = std::move(text)]() mutable {
    if (self->texts_.size() >= kMaxQueuedTexts) self->texts_.pop_front();
    self->texts_.push_back(std::move(text));
    self->do_write();
  });
}

void AgentSession::do_write() {
  if (writing_ || closing_ || station_id_ == 0 || !ws_.is_open()) return;
  if (!texts_.empty()) {
    text_in_flight_ = std::move(texts_.front());
    texts_.pop_front();
    writing_ = true;
    ws_.text(true);
    return ws_.async_write(net::buffer(text_in_flight_),
                           beast::bind_front_handler(&AgentSession::on_write, shared_from_this()));
  }
  for (std::size_t i = 0; i < pending_models_.size(); ++i) {
    // Round robin from the device after the last one sent, so one hand never starves the other.
    const std::size_t device = (next_model_device_ + i) % pending_models_.size();
    if (!model_pending_[device]) continue;
    model_pending_[device] = false;
    next_model_device_ = device + 1;
    const auto size =
        devices::encode(pending_models_[device], send_sequence_++, monotonic_us(), model_frame_);
    writing_ = true;
    ws_.binary(true);
    return ws_.async_write(net::buffer(model_frame_.data(), size),
                           beast::bind_front_handler(&AgentSession::on_write, shared_from_this()));
  }
}

void AgentSession::on_write(beast::error_code ec, std::size_t) {
  writing_ = false;
  if (ec) return;
  do_write();
}

void AgentSession::handle_device_state() {
  const auto data = buffer_.cdata();
  const auto result = devices::decode(
      std::span<const std::uint8_t>(static_cast<const std::uint8_t*>(data.data()), data.size()));
  if (!result) {
    return do_close(websocket::close_code::bad_payload, std::string(result.reason()));
  }
  const std::uint32_t sequence = result.message().header.sequence;
  // Unsigned: a wrap is a small gap, a repeat or a step back (never on TCP) is ignored.
  if (states_received_ > 0 && sequence - last_sequence_ > 1 &&
      sequence - last_sequence_ < 0x80000000u) {
    window_states_lost_ += sequence - last_sequence_ - 1;
  }
  ++window_states_;
  last_sequence_ = sequence;
  // Only the station's newest link drives its session: a second agent with the same token (or
  // the old link of a reconnect) must not interleave its hand with the current one.
  if (app_->agent_for_station(station_id_).get() == this) {
    app_->live_sessions().on_device_state(station_id_, result.message().state,
                                          result.message().header.timestamp_us);
  }
  ++states_received_;
  do_read();
}

void AgentSession::close(std::string reason) {
  net::post(ws_.get_executor(), [self = shared_from_this(), reason = std::move(reason)] {
    self->do_close(websocket::close_code::going_away, reason);
  });
}

void AgentSession::do_close(websocket::close_code code, std::string reason) {
  if (closing_ || !ws_.is_open()) return;
  closing_ = true;
  hello_timer_.cancel();
  ws_.async_close(websocket::close_reason(code, close_reason_text(reason)),
                  [self = shared_from_this()](beast::error_code) {});
}

}  // namespace incise::server
