#pragma once
// The agent's supervisor: runs the haptic loop on its own thread for the agent's whole life,
// keeps one StationLink to the server alive, reconnecting with backoff, stops on SIGINT/SIGTERM,
// logs the bridge statistics on SIGUSR1 and at exit, and keeps the totals for the summary line.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>

#include "devices/agent/backoff.h"
#include "devices/agent/haptic_channel.h"
#include "devices/agent/haptic_loop.h"
#include "devices/agent/options.h"
#include "devices/agent/station_link.h"
#include "devices/device.h"
#include "devices/state_log.h"

namespace incise::devices::agent {

// Process exit codes (documented in --help).
inline constexpr int kExitStopped = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;
inline constexpr int kExitRefused = 3;

class Agent {
 public:
  // The devices (one per hand, at most kMaxDevices) and the recorder (may be null: no
  // --record-states) must outlive the agent; `tls` verifies a wss:// server (null for ws://).
  // Nothing happens until start().
  Agent(asio::io_context& io, const AgentOptions& options, std::vector<Device*> devices,
        StateLogWriter* recorder = nullptr, std::shared_ptr<asio::ssl::context> tls = nullptr);

  // Starts the haptic loop, connects and keeps connecting; the io_context runs out of work once
  // the agent has stopped.
  void start();
  // Stops as SIGTERM does; any thread.
  void request_stop();
  // After the io_context has run out of work: stops the haptic loop (the force fades out), then
  // logs the statistics and the summary.
  void finish();

  int exit_code() const { return exit_code_; }

  // io thread, or after finish().
  const BridgeStats& bridge_stats() const { return stats_; }
  uint64_t states_dropped() const { return channel_.states.dropped(); }
  // Any thread.
  LoopSummary loop_summary() const { return loop_.summary(); }

  // States the deadband held back, all devices.
  uint64_t held_states() const;
  // The haptic loop (the thread that runs it, or any once finished).
  const HapticLoop& loop() const { return loop_; }
  // One line: loop rate and timing, round trip, states sent and dropped, models received.
  std::string stats_line() const;

 private:
  void do_connect();
  void on_welcome(const Welcome& welcome);
  void on_link_end(const LinkEnd& end);
  void do_retry(Backoff::Duration delay);
  void on_retry(beast::error_code ec);
  void on_signal(beast::error_code ec, int signal_number);
  void do_wait_stats_signal();
  void stop();
  void log_summary() const;

  asio::io_context& io_;
  LinkSettings settings_;
  std::vector<Device*> devices_;
  HapticChannel channel_;
  HapticLoop loop_;
  BridgeStats stats_;
  asio::signal_set signals_;
  asio::signal_set stats_signal_;  // SIGUSR1
  asio::steady_timer retry_timer_;
  Backoff backoff_;
  std::shared_ptr<StationLink> link_;

  bool stopping_ = false;
  int exit_code_ = kExitStopped;
  int attempt_ = 0;  // attempts since the last successful connection
  int connections_ = 0;
  uint64_t messages_sent_ = 0;
  Clock::duration connected_for_{};
  double send_rate_hz_ = 0.0;  // 1000 Hz / k
  bool deadband_ = true;
};

}  // namespace incise::devices::agent
