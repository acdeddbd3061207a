#include "server/view_session.h"

#include <algorithm>
#include <charconv>
#include <nlohmann/json.hpp>
#include <optional>

#include "server/view_message.h"
#include "server/wire_text.h"

namespace incise::server {

namespace beast = boost::beast;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using SteadyClock = std::chrono::steady_clock;

namespace {

constexpr auto kMetricsPeriod = std::chrono::milliseconds(100);

int query_int(std::string_view query, std::string_view key, int fallback, int lo, int hi) {
  const auto text = query_value(query, key);
  if (!text) return fallback;
  int value = 0;
  const auto [p, ec] = std::from_chars(text->data(), text->data() + text->size(), value);
  if (ec == std::errc{} && p == text->data() + text->size()) return std::clamp(value, lo, hi);
  return fallback;
}

}  // namespace

ViewRequest parse_view_query(std::string_view target) {
  const auto q = target.find('?');
  const auto query = q == std::string_view::npos ? std::string_view{} : target.substr(q + 1);
  ViewRequest r;
  r.fps = query_int(query, "fps", r.fps, 1, 60);
  r.width = query_int(query, "width", r.width, 160, 1280);
  r.height = query_int(query, "height", r.height, 120, 960);
  r.outside = query_value(query, "view") == "outside";
  return r;
}

// The viewer as the render thread sees it. It never holds the ViewSession itself (only a weak
// pointer, locked on the socket's executor), so the session is never destroyed on the render
// thread, which its replay's destructor would have to join.
class ViewSession::Sink final : public live::FrameSink {
 public:
  Sink(net::any_io_executor executor, std::weak_ptr<ViewSession> view, ViewRequest request)
      : executor_(std::move(executor)), view_(std::move(view)) {
    configure(request.fps, request.width, request.height, request.outside);
  }

  void configure(std::optional<int> fps, std::optional<int> width, std::optional<int> height,
                 std::optional<bool> outside) {
    if (outside) outside_ = *outside;
    if (fps) period_ns_ = 1'000'000'000 / std::clamp(*fps, 1, 60);
    if (width) width_ = std::clamp(*width, 160, 1280);
    if (height) height_ = std::clamp(*height, 120, 960);
    if (outside || width || height) ++version_;
  }
  void acknowledge(std::int64_t frame) {
    std::int64_t seen = acked_.load();
    while (frame > seen && !acked_.compare_exchange_weak(seen, frame)) {
    }
  }
  std::int64_t issued() const { return issued_.load(); }

  std::uint64_t settings_version() const override { return version_.load(); }

  std::optional<Request> frame_wanted(SteadyClock::time_point now) override {
    if (issued_.load() - acked_.load() >= kMaxFramesInFlight) return std::nullopt;
    const auto t = now.time_since_epoch().count();
    if (t < next_due_ns_) return std::nullopt;
    next_due_ns_ = t + period_ns_.load();
    return Request{width_.load(), height_.load(), outside_.load()};
  }

  void deliver(std::uint32_t frame_number, std::shared_ptr<const std::vector<std::uint8_t>> message,
               SteadyClock::time_point published_at) override {
    issued_.store(frame_number);
    net::post(executor_, [view = view_, message = std::move(message), published_at] {
      if (auto v = view.lock()) v->on_frame(message, published_at);
    });
  }

 private:
  static_assert(std::is_same_v<SteadyClock::duration, std::chrono::nanoseconds>);
  net::any_io_executor executor_;
  std::weak_ptr<ViewSession> view_;
  std::atomic<std::int64_t> period_ns_{0};
  std::atomic<int> width_{640};
  std::atomic<int> height_{480};
  std::atomic<bool> outside_{false};
  std::atomic<std::uint64_t> version_{0};
  std::atomic<std::int64_t> issued_{0};
  std::atomic<std::int64_t> acked_{0};
  std::int64_t next_due_ns_ = 0;  // render thread only
};

ViewSession::ViewSession(transport::MaybeTlsStream&& stream,
                         std::shared_ptr<live::LiveSession> session, bool outside_view_allowed)
    : ViewSession(std::move(stream), std::move(session), nullptr, outside_view_allowed) {}

ViewSession::ViewSession(transport::MaybeTlsStream&& stream,
                         std::unique_ptr<live::ReplaySession> replay, bool outside_view_allowed)
    : ViewSession(std::move(stream), nullptr, std::move(replay), outside_view_allowed) {}

ViewSession::ViewSession(transport::MaybeTlsStream&& stream,
                         std::shared_ptr<live::LiveSession> session,
                         std::unique_ptr<live::ReplaySession> replay, bool outside_view_allowed)
    : ws_(std::move(stream)),
      metrics_timer_(ws_.get_executor()),
      live_(std::move(session)),
      replay_(std::move(replay)),
      outside_view_allowed_(outside_view_allowed) {}

ViewSession::~ViewSession() {
  sink_.reset();
  replay_.reset();  // joins the replay's threads; they never wait for this socket
}

live::StreamSource& ViewSession::source() const {
  if (replay_) return *replay_;
  return *live_;
}

live::FrameStreamer& ViewSession::streamer() const {
  if (replay_) return replay_->streamer();
  return live_->streamer();
}

void ViewSession::run(beast::http::request<beast::http::string_body> upgrade) {
  // The sink needs a weak pointer to this, which exists only now.
  auto request = parse_view_query(upgrade.target());
  request.outside = request.outside && outside_view_allowed_;
  sink_ = std::make_shared<Sink>(ws_.get_executor(), weak_from_this(), request);
  ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
  ws_.read_message_max(kMaxClientMessage);
  ws_.async_accept(upgrade, beast::bind_front_handler(&ViewSession::on_accept, shared_from_this()));
}

void ViewSession::on_accept(beast::error_code ec) {
  if (ec) return;
  if (replay_) replay_->start();
  streamer().add(sink_);
  send_metrics();
  schedule_metrics();
  do_read();
}

void ViewSession::do_read() {
  buffer_.clear();
  ws_.async_read(buffer_, beast::bind_front_handler(&ViewSession::on_read, shared_from_this()));
}

void ViewSession::on_read(beast::error_code ec, std::size_t) {
  if (ec) {
    // closing_ first: a timer that already expired may still run its handler after cancel().
    closing_ = true;
    metrics_timer_.cancel();
    return;
  }
  if (closing_) return;
  if (!ws_.got_text()) {
    return do_close(websocket::close_code::bad_payload, "binary messages are not accepted here");
  }
  const auto parsed = parse_view_message(beast::buffers_to_string(buffer_.data()), sink_->issued(),
                                         replay_ != nullptr);
  if (!parsed.message) return do_close(websocket::close_code::bad_payload, parsed.error);
  if (parsed.message->outside.value_or(false) && !outside_view_allowed_) {
    return do_close(websocket::close_code::policy_error,
                    "only instructors and admins may switch to the outside view");
  }
  apply(*parsed.message);
  do_read();
}

void ViewSession::apply(const ViewMessage& m) {
  switch (m.type) {
    case ViewMessage::Type::ack:
      sink_->acknowledge(m.frame);
      streamer().poke();
      break;
    case ViewMessage::Type::configure:
      sink_->configure(m.fps, m.width, m.height, m.outside);
      streamer().poke();
      break;
    case ViewMessage::Type::play:
      replay_->play();
      break;
    case ViewMessage::Type::pause:
      replay_->pause();
      break;
    case ViewMessage::Type::speed:
      replay_->set_speed(m.value);
      break;
    case ViewMessage::Type::seek:
      replay_->seek(m.value);
      break;
  }
}

void ViewSession::on_frame(std::shared_ptr<const std::vector<std::uint8_t>> message,
                           SteadyClock::time_point published_at) {
  pending_frame_ = std::move(message);  // an unsent older frame is simply replaced
  pending_published_at_ = published_at;
  do_write();
}

void ViewSession::schedule_metrics() {
  metrics_timer_.expires_after(kMetricsPeriod);
  metrics_timer_.async_wait([self = shared_from_this()](beast::error_code ec) {
    if (ec || self->closing_ || !self->ws_.is_open()) return;
    self->send_metrics();
    if (!self->closing_) self->schedule_metrics();
  });
}

void ViewSession::send_metrics() {
  if (ended_sent_) return;
  nlohmann::json m = source().status();
  m["type"] = "metrics";
  if (const auto s = source().snapshot()) {
    m["sim_time_s"] = s->sim_time_s;
    m["steps"] = s->tick;
    m["tool"] = {s->tool_tip.x(), s->tool_tip.y(), s->tool_tip.z()};
    m["force_n"] = s->force_n.norm();
    m["peak_force_n"] = s->peak_force_n;
    m["damage_index"] = s->damage_index;
    m["peak_strain"] = s->peak_strain;
    m["path_length_m"] = s->path_length_m;
    m["contact"] = s->contact;
    if (s->cutting) {
      m["cut_area_m2"] = s->cut_area_m2;
      m["cut_mean_distance_m"] = s->cut_mean_distance_m;
      m["never_event"] = s->never_event;
      m["inverted_tets_pulled"] = s->inverted_tets_pulled;
    }
    if (s->hands > 1) {
      m["tool_2"] = {s->second_tool_tip.x(), s->second_tool_tip.y(), s->second_tool_tip.z()};
      m["force_2_n"] = s->second_force_n.norm();
    }
  }
  m["frames_sent"] = frames_sent_;
  // This viewer's: whether it may switch to the outside view (api::may_look_outside).
  m["outside_view_allowed"] = outside_view_allowed_;
  if (live_ && live_->state() == live::LiveState::finished) {
    ended_sent_ = true;
    pending_text_ = dump_json(m);
    do_write();
    // The final metrics go first, then the end notice (do_write sends texts in order).
    end_notice_ = dump_json({{"type", "ended"}, {"reason", live_->reason()}});
    return do_write();
  }
  pending_text_ = dump_json(m);
  do_write();
}

void ViewSession::do_write() {
  if (writing_ || closing_) return;
  if (pending_text_ || end_notice_) {
    if (pending_text_) {
      text_in_flight_ = std::move(*pending_text_);
      pending_text_.reset();
    } else {
      text_in_flight_ = std::move(*end_notice_);
      end_notice_.reset();
      end_in_flight_ = true;
    }
    writing_ = true;
    ws_.text(true);
    return ws_.async_write(net::buffer(text_in_flight_),
                           beast::bind_front_handler(&ViewSession::on_write, shared_from_this()));
  }
  if (ended_sent_) return;  // no frames after the end
  if (pending_frame_) {
    frame_in_flight_ = std::move(pending_frame_);
    pending_frame_.reset();
    const double latency_ms =
        std::chrono::duration<double, std::milli>(SteadyClock::now() - pending_published_at_)
            .count();
    source().frame_latency().add(latency_ms);
    ++frames_sent_;
    writing_ = true;
    ws_.binary(true);
    return ws_.async_write(net::buffer(*frame_in_flight_),
                           beast::bind_front_handler(&ViewSession::on_write, shared_from_this()));
  }
}

void ViewSession::on_write(beast::error_code ec, std::size_t) {
  writing_ = false;
  frame_in_flight_.reset();
  if (ec) {
    closing_ = true;
    metrics_timer_.cancel();
    return;
  }
  if (end_in_flight_) {
    end_in_flight_ = false;
    return do_close(websocket::close_code::normal, "session ended");
  }
  do_write();
}

void ViewSession::close(websocket::close_code code, std::string reason) {
  net::post(ws_.get_executor(), [self = shared_from_this(), code, reason = std::move(reason)] {
    self->do_close(code, reason);
  });
}

void ViewSession::do_close(websocket::close_code code, std::string reason) {
  if (closing_ || !ws_.is_open()) return;
  closing_ = true;
  metrics_timer_.cancel();
  ws_.async_close(websocket::close_reason(code, close_reason_text(reason)),
                  [self = shared_from_this()](beast::error_code) {});
}

}  // namespace incise::server
