#pragma once
// The agent's supervisor: keeps one StationLink to the server alive, reconnecting with backoff,
// stops on SIGINT/SIGTERM, and keeps the totals for the summary line.

#include <cstdint>
#include <memory>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>

#include "devices/agent/backoff.h"
#include "devices/agent/options.h"
#include "devices/agent/station_link.h"
#include "devices/device.h"

namespace incise::devices::agent {

// Process exit codes (documented in --help).
inline constexpr int kExitStopped = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;
inline constexpr int kExitRefused = 3;

class Agent {
 public:
  // device must outlive the agent. Nothing happens until start().
  Agent(asio::io_context& io, const AgentOptions& options, Device& device);

  // Connects and keeps connecting; the io_context runs out of work once the agent has stopped.
  void start();

  int exit_code() const { return exit_code_; }
  void log_summary() const;

 private:
  void do_connect();
  void on_welcome(const Welcome& welcome);
  void on_link_end(const LinkEnd& end);
  void do_retry(Backoff::Duration delay);
  void on_retry(beast::error_code ec);
  void on_signal(beast::error_code ec, int signal_number);
  void stop();

  asio::io_context& io_;
  LinkSettings settings_;
  Device& device_;
  asio::signal_set signals_;
  asio::steady_timer retry_timer_;
  Backoff backoff_;
  std::shared_ptr<StationLink> link_;

  bool stopping_ = false;
  int exit_code_ = kExitStopped;
  int attempt_ = 0;  // attempts since the last successful connection
  int connections_ = 0;
  uint64_t messages_sent_ = 0;
  Clock::duration connected_for_{};
};

}  // namespace incise::devices::agent
