#include "fake_station_server.h"

#include <array>
#include <mutex>
#include <span>

#include <boost/asio/strand.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

#include "devices/protocol.h"

namespace incise::devices::agent::testing {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;

struct FakeStationServer::State {
  FakeStationBehaviour behaviour;
  mutable std::mutex mutex;
  FakeStationRecord record;

  template <typename F>
  void update(F&& change) {
    std::lock_guard lock(mutex);
    change(record);
  }
};

namespace {

class Session : public std::enable_shared_from_this<Session> {
 public:
  Session(tcp::socket socket, std::shared_ptr<FakeStationServer::State> state)
      : ws_(std::move(socket)), state_(std::move(state)) {}

  void run() {
    ws_.read_message_max(kMaxMessageSize);
    ws_.async_accept(beast::bind_front_handler(&Session::on_accept, shared_from_this()));
  }

 private:
  void on_accept(beast::error_code ec) {
    if (ec) return fail(ec, "accept");
    state_->update([this](FakeStationRecord& r) { connection_ = ++r.connections; });
    ws_.async_read(buffer_, beast::bind_front_handler(&Session::on_hello, shared_from_this()));
  }

  void on_hello(beast::error_code ec, std::size_t) {
    if (ec) return fail(ec, "read hello");
    const auto hello = parse_hello(beast::buffers_to_string(buffer_.data()));
    buffer_.consume(buffer_.size());
    if (!hello) return do_close(websocket::close_code::policy_error, hello.error);
    if (hello.value->station_token != state_->behaviour.accepted_token) {
      return do_close(websocket::close_code::policy_error, "unknown station token");
    }
    state_->update([&](FakeStationRecord& r) { r.agents.push_back(hello.value->agent); });
    welcome_ = build_welcome({7, "Bench 7", ""});
    ws_.text(true);
    ws_.async_write(asio::buffer(welcome_),
                    beast::bind_front_handler(&Session::on_welcome_sent, shared_from_this()));
  }

  void on_welcome_sent(beast::error_code ec, std::size_t) {
    if (ec) return fail(ec, "write welcome");
    if (!state_->behaviour.session_notice.empty()) {
      return ws_.async_write(
          asio::buffer(state_->behaviour.session_notice),
          beast::bind_front_handler(&Session::on_notice_sent, shared_from_this()));
    }
    on_notice_sent({}, 0);
  }

  void on_notice_sent(beast::error_code ec, std::size_t) {
    if (ec) return fail(ec, "write session notice");
    ws_.binary(true);
    do_read();
  }

  // Answers the state stamped timestamp_us with a model, or with a bad one when told to.
  void maybe_send_model(uint64_t timestamp_us) {
    const FakeStationBehaviour& b = state_->behaviour;
    const bool bad =
        connection_ == 1 && b.bad_model_after > 0 && frames_ >= b.bad_model_after && !bad_sent_;
    if (write_in_flight_ || (!b.force_model && !bad)) return;
    bad_sent_ = bad_sent_ || bad;
    ForceModel model = b.force_model.value_or(ForceModel{});
    model.state_timestamp_us = timestamp_us;
    if (bad) model.force = {150.0, 0.0, 0.0};
    const std::size_t size = encode(model, model_sequence_++, timestamp_us, model_frame_);
    write_in_flight_ = true;
    ws_.async_write(asio::buffer(model_frame_.data(), size),
                    beast::bind_front_handler(&Session::on_model_sent, shared_from_this()));
  }

  void on_model_sent(beast::error_code ec, std::size_t) {
    write_in_flight_ = false;
    if (ec) return fail(ec, "write model");
    state_->update([](FakeStationRecord& r) { ++r.models_sent; });
  }

  void do_read() {
    ws_.async_read(buffer_, beast::bind_front_handler(&Session::on_read, shared_from_this()));
  }

  void on_read(beast::error_code ec, std::size_t) {
    if (ec) return fail(ec, "read");
    const auto bytes = buffer_.cdata();
    const DecodeResult result =
        decode(std::span<const uint8_t>(static_cast<const uint8_t*>(bytes.data()), bytes.size()));
    const bool text = ws_.got_text();
    const std::string text_body =
        text ? std::string(static_cast<const char*>(bytes.data()), bytes.size()) : std::string();
    buffer_.consume(buffer_.size());
    state_->update([&](FakeStationRecord& r) {
      if (text) {
        // The only text the agent sends after the welcome is its link report.
        auto report = parse_link_report(text_body);
        if (report) {
          r.link_reports.push_back(std::move(*report.value));
        } else {
          r.errors.push_back("text frame after welcome: " + report.error);
        }
      } else if (!result) {
        r.errors.push_back("bad frame: " + std::string(result.reason()));
      } else {
        const FrameHeader& h = result.message().header;
        r.frames.push_back(
            {connection_, h.sequence, h.timestamp_us, std::chrono::steady_clock::now()});
      }
    });
    if (text) return do_read();
    ++frames_;
    const int drop_after = state_->behaviour.drop_first_connection_after;
    if (connection_ == 1 && drop_after > 0 && frames_ == drop_after) {
      return do_close(websocket::close_code::going_away, "test drops the link");
    }
    if (result) maybe_send_model(result.message().header.timestamp_us);
    do_read();
  }

  void do_close(websocket::close_code code, const std::string& reason) {
    ws_.async_close(websocket::close_reason(code, reason),
                    beast::bind_front_handler(&Session::on_close, shared_from_this()));
  }

  void on_close(beast::error_code) {}

  void fail(beast::error_code ec, const char* what) {
    if (ec == websocket::error::closed) {
      const websocket::close_reason& reason = ws_.reason();
      state_->update([&](FakeStationRecord& r) {
        r.agent_close_codes.push_back(reason.code);
        r.agent_close_reasons.emplace_back(reason.reason.data(), reason.reason.size());
      });
      return;
    }
    // The agent vanishing (killed, or dropping a refused link) is part of the tests.
    if (ec == asio::error::operation_aborted || ec == beast::error::timeout ||
        ec == asio::error::eof || ec == asio::error::connection_reset) {
      return;
    }
    state_->update(
        [&](FakeStationRecord& r) { r.errors.push_back(std::string(what) + ": " + ec.message()); });
  }

  websocket::stream<beast::tcp_stream> ws_;
  std::shared_ptr<FakeStationServer::State> state_;
  beast::flat_buffer buffer_;
  std::string welcome_;
  std::array<uint8_t, kForceModelFrameSize> model_frame_{};
  uint32_t model_sequence_ = 0;
  bool write_in_flight_ = false;
  bool bad_sent_ = false;
  int connection_ = 0;
  int frames_ = 0;
};

}  // namespace

FakeStationServer::FakeStationServer(FakeStationBehaviour behaviour)
    : acceptor_(io_, tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0)),
      port_(acceptor_.local_endpoint().port()),
      state_(std::make_shared<State>()) {
  state_->behaviour = std::move(behaviour);
  do_accept();
  thread_ = std::thread([this] { io_.run(); });
}

FakeStationServer::~FakeStationServer() {
  io_.stop();
  thread_.join();
}

std::string FakeStationServer::url() const {
  return "ws://127.0.0.1:" + std::to_string(port_) + "/agent";
}

FakeStationRecord FakeStationServer::record() const {
  std::lock_guard lock(state_->mutex);
  return state_->record;
}

void FakeStationServer::do_accept() {
  acceptor_.async_accept(asio::make_strand(io_), [this](beast::error_code ec, tcp::socket socket) {
    if (ec) return;
    std::make_shared<Session>(std::move(socket), state_)->run();
    do_accept();
  });
}

}  // namespace incise::devices::agent::testing
