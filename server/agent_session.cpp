#include "server/agent_session.h"

#include <iostream>
#include <mutex>

#include "db/stations_repo.h"
#include "devices/protocol.h"

namespace incise::server {

namespace beast = boost::beast;
namespace websocket = beast::websocket;
namespace net = boost::asio;

AgentSession::AgentSession(net::ip::tcp::socket&& socket, std::shared_ptr<AppState> app)
    : ws_(std::move(socket)), app_(std::move(app)) {}

AgentSession::~AgentSession() {
  if (station_id_ != 0) {
    app_->agent_left(this);
    std::cerr << "incise-server: station " << station_id_ << " agent disconnected\n";
  }
}

void AgentSession::run(beast::http::request<beast::http::string_body> upgrade) {
  ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
  ws_.read_message_max(devices::kMaxMessageSize);
  ws_.async_accept(upgrade,
                   beast::bind_front_handler(&AgentSession::on_accept, shared_from_this()));
}

void AgentSession::on_accept(beast::error_code ec) {
  if (ec) return;
  do_read();
}

void AgentSession::do_read() {
  buffer_.clear();
  ws_.async_read(buffer_, beast::bind_front_handler(&AgentSession::on_read, shared_from_this()));
}

void AgentSession::on_read(beast::error_code ec, std::size_t) {
  if (ec == websocket::error::message_too_big) {
    return do_close(websocket::close_code::too_big,
                    "message exceeds " + std::to_string(devices::kMaxMessageSize) + " bytes");
  }
  if (ec) return;  // closed, timed out or reset: the destructor marks the station offline
  if (closing_) return;
  if (station_id_ == 0) return handle_hello();
  if (ws_.got_text()) {
    return do_close(websocket::close_code::policy_error,
                    "text messages after the hello are not part of protocol 1");
  }
  handle_device_state();
}

void AgentSession::handle_hello() {
  if (!ws_.got_text()) {
    return do_close(websocket::close_code::policy_error, "the first message must be the hello");
  }
  const auto hello = devices::parse_hello(beast::buffers_to_string(buffer_.data()));
  if (!hello) return do_close(websocket::close_code::policy_error, hello.error);

  std::optional<db::Station> station;
  {
    std::lock_guard lock(app_->db_mutex());
    station = db::StationsRepo(app_->db()).find_by_token(hello.value->station_token);
  }
  if (!station) return do_close(websocket::close_code::policy_error, "unknown station token");

  station_id_ = station->id;
  app_->agent_joined(station_id_, shared_from_this());
  std::cerr << "incise-server: station " << station->id << " (" << station->name
            << ") agent connected: " << hello.value->agent << "\n";
  outgoing_ = devices::build_welcome({station->id, station->name});
  ws_.text(true);
  ws_.async_write(net::buffer(outgoing_),
                  beast::bind_front_handler(&AgentSession::on_write, shared_from_this()));
}

void AgentSession::on_write(beast::error_code ec, std::size_t) {
  if (ec) return;
  do_read();
}

void AgentSession::handle_device_state() {
  const auto data = buffer_.cdata();
  const auto result = devices::decode(
      std::span<const std::uint8_t>(static_cast<const std::uint8_t*>(data.data()), data.size()));
  if (!result) {
    return do_close(websocket::close_code::bad_payload, std::string(result.reason()));
  }
  // The simulation session (next issue) consumes these; for now the link counts them.
  last_sequence_ = result.message().header.sequence;
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
  if (reason.size() > devices::kMaxCloseReasonSize) reason.resize(devices::kMaxCloseReasonSize);
  ws_.async_close(websocket::close_reason(code, reason),
                  [self = shared_from_this()](beast::error_code) {});
}

}  // namespace incise::server
