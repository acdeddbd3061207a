#include "devices/agent/agent.h"

#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>

#include <boost/asio/post.hpp>

#include "devices/agent/log.h"

#ifndef INCISE_AGENT_VERSION
#define INCISE_AGENT_VERSION "dev"
#endif

namespace incise::devices::agent {
namespace {

LinkSettings make_settings(const AgentOptions& options, const std::vector<Device*>& devices,
                           StateLogWriter* recorder, std::shared_ptr<asio::ssl::context> tls) {
  LinkSettings settings;
  settings.server = options.server;
  settings.tls = std::move(tls);
  settings.hello.station_token = options.token;
  std::string names;
  for (const Device* device : devices)
    names += (names.empty() ? "" : " + ") + std::string(device->name());
  settings.hello.agent = "incise-agent/" INCISE_AGENT_VERSION " (" + names + ")";
  settings.device_count = devices.size();
  if (recorder != nullptr) {
    settings.recorder = [recorder](const TimedState& timed) {
      recorder->write(timed.state, timed.timestamp_us);
    };
  }
  // The server refuses a longer hello; the description is informative only, so cut it (on a
  // UTF-8 character boundary: continuation bytes are 10xxxxxx).
  std::string& agent = settings.hello.agent;
  if (agent.size() > kMaxNameSize) {
    std::size_t end = kMaxNameSize;
    while (end > 0 && (static_cast<unsigned char>(agent[end]) & 0xC0) == 0x80)
      --end;
    agent.resize(end);
  }
  settings.epoch = Clock::now();
  return settings;
}

// The haptic loop hands every k-th state to the network: k = round(1000 Hz / rate).
int send_every(double rate_hz) {
  return std::max(1, static_cast<int>(std::lround(1000.0 / rate_hz)));
}

std::string format(const char* format, auto... values) {
  char text[256];
  std::snprintf(text, sizeof text, format, values...);
  return text;
}

LoopSettings loop_settings(const AgentOptions& options) {
  LoopSettings settings;
  settings.send_every = send_every(options.rate_hz);
  settings.deadband.enabled = options.deadband;
  settings.guard = options.guard;
  return settings;
}

}  // namespace

Agent::Agent(asio::io_context& io, const AgentOptions& options, std::vector<Device*> devices,
             StateLogWriter* recorder, std::shared_ptr<asio::ssl::context> tls)
    : io_(io),
      settings_(make_settings(options, devices, recorder, std::move(tls))),
      devices_(std::move(devices)),
      loop_(devices_, channel_, loop_settings(options), settings_.epoch),
      signals_(io, SIGINT, SIGTERM),
      stats_signal_(io, SIGUSR1),
      retry_timer_(io),
      send_rate_hz_(1000.0 / send_every(options.rate_hz)),
      deadband_(options.deadband) {}

void Agent::start() {
  for (std::size_t i = 0; i < devices_.size(); ++i) {
    const DeviceCapabilities caps = devices_[i]->capabilities();
    log_line("device " + std::to_string(i) + ": " + std::string(devices_[i]->name()) +
             (caps.has_force_output ? ", force output" : ", no force output (forces on screen)"));
  }
  log_line(format("haptic loop at 1000 Hz, sending states at %g Hz (deadband %s) to ",
                  send_rate_hz_, deadband_ ? "on" : "off") +
           settings_.server.url());
  loop_.start();
  signals_.async_wait(
      [this](beast::error_code ec, int signal_number) { on_signal(ec, signal_number); });
  do_wait_stats_signal();
  do_connect();
}

void Agent::request_stop() {
  asio::post(io_, [this] { stop(); });
}

void Agent::finish() {
  loop_.stop();
  log_line(stats_line());
  log_summary();
}

void Agent::do_wait_stats_signal() {
  stats_signal_.async_wait([this](beast::error_code ec, int) {
    if (ec || stopping_) return;
    log_line(stats_line());
    do_wait_stats_signal();
  });
}

std::string Agent::stats_line() const {
  const LoopSummary loop = loop_.summary();
  const Histogram& round_trip = stats_.round_trip_us;
  return format(
      "stats: loop %.1f Hz, period p50 %.0f us p99 %.0f us, max jitter %.0f us, %llu overruns; "
      "round trip p50 %.2f ms p99 %.2f ms (%llu models); states sent %llu, dropped %llu; force "
      "models received %llu, lost %llu; states held by the deadband %llu",
      loop.rate_hz, loop.period_p50_us, loop.period_p99_us, loop.max_jitter_us,
      static_cast<unsigned long long>(loop.overruns), round_trip.percentile(50) / 1000.0,
      round_trip.percentile(99) / 1000.0, static_cast<unsigned long long>(round_trip.count()),
      static_cast<unsigned long long>(stats_.states_sent),
      static_cast<unsigned long long>(channel_.states.dropped()),
      static_cast<unsigned long long>(stats_.models_received),
      static_cast<unsigned long long>(stats_.models_lost),
      static_cast<unsigned long long>(held_states()));
}

uint64_t Agent::held_states() const {
  uint64_t held = 0;
  for (const DeviceTelemetry& t : channel_.telemetry)
    held += t.states_held.load();
  return held;
}

void Agent::do_connect() {
  ++attempt_;
  link_ = std::make_shared<StationLink>(
      io_, settings_, channel_, stats_, [this](const Welcome& welcome) { on_welcome(welcome); },
      [this](const LinkEnd& end) { on_link_end(end); });
  link_->run();
}

void Agent::on_welcome(const Welcome& welcome) {
  ++connections_;
  attempt_ = 0;
  backoff_.reset();
  log_line("connected to " + settings_.server.url() + " as station " +
           std::to_string(welcome.station_id) + " \"" + welcome.station_name + "\"");
}

void Agent::on_link_end(const LinkEnd& end) {
  link_.reset();
  messages_sent_ += end.messages_sent;
  connected_for_ += end.connected_for;
  // Whatever cut a link short while stopping, there is nothing left to retry or report.
  if (stopping_ && end.kind != LinkEnd::Kind::Refused) return;
  switch (end.kind) {
    case LinkEnd::Kind::Stopped:
      return;
    case LinkEnd::Kind::Refused:
      log_line("server refused: " + (end.reason.empty() ? "(no reason given)" : end.reason));
      exit_code_ = kExitRefused;
      return stop();
    case LinkEnd::Kind::Failed: {
      const auto delay = backoff_.next();
      log_line("connection attempt " + std::to_string(attempt_) + " to " + settings_.server.url() +
               " failed: " + end.reason + "; retrying in " + format_seconds(delay));
      return do_retry(delay);
    }
    case LinkEnd::Kind::Dropped: {
      const auto delay = backoff_.next();
      log_line("link lost after " + format_seconds(end.connected_for) + ": " + end.reason +
               "; reconnecting in " + format_seconds(delay));
      return do_retry(delay);
    }
  }
}

void Agent::do_retry(Backoff::Duration delay) {
  if (stopping_) return;
  retry_timer_.expires_after(delay);
  retry_timer_.async_wait([this](beast::error_code ec) { on_retry(ec); });
}

void Agent::on_retry(beast::error_code ec) {
  if (ec || stopping_) return;
  do_connect();
}

void Agent::on_signal(beast::error_code ec, int signal_number) {
  if (ec) return;  // cancelled by stop()
  log_line(std::string("caught ") + (signal_number == SIGINT ? "SIGINT" : "SIGTERM") + ", closing");
  stop();
}

void Agent::stop() {
  if (stopping_) return;
  stopping_ = true;
  // Give SIGINT/SIGTERM their default action back: a second Ctrl-C ends a stuck agent at once.
  beast::error_code ignored;
  signals_.clear(ignored);
  signals_.cancel(ignored);
  stats_signal_.cancel(ignored);
  retry_timer_.cancel();
  if (link_) link_->stop();
}

void Agent::log_summary() const {
  const auto running = Clock::now() - settings_.epoch;
  log_line("stopped: sent " + std::to_string(messages_sent_) + " device states over " +
           std::to_string(connections_) + (connections_ == 1 ? " connection" : " connections") +
           ", connected " + format_seconds(connected_for_) + " of " + format_seconds(running));
}

}  // namespace incise::devices::agent
