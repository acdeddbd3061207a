#pragma once
// The server side of the /agent WebSocket, in-process, for testing the real agent: accepts a
// hello with a known token (else closes 1008 "unknown station token"), answers with a welcome,
// then decodes and records every device-state frame, and optionally answers each with a force
// model echoing its timestamp, as the real server does. Runs on its own thread on 127.0.0.1 at a
// port the OS picks.

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>

#include "devices/protocol.h"

namespace incise::devices::agent::testing {

struct FakeStationBehaviour {
  std::string accepted_token = "good-token";
  // Close the first connection with 1001 (going away) after this many frames; 0 = never.
  int drop_first_connection_after = 0;
  // Answer each device state with this model (state_timestamp_us set to the state's timestamp),
  // unless the previous answer is still being written.
  std::optional<ForceModel> force_model;
  // Sent as a text frame right after the welcome, unless empty.
  std::string session_notice;
  // After this many frames on the first connection send a ForceModel frame with |force| 150 N
  // (invalid) instead of force_model; 0 = never.
  int bad_model_after = 0;
};

struct ReceivedFrame {
  int connection = 0;  // 1 for the first accepted WebSocket, 2 for the next, ...
  uint32_t sequence = 0;
  uint64_t timestamp_us = 0;
  std::chrono::steady_clock::time_point received;
};

struct FakeStationRecord {
  int connections = 0;                 // WebSocket upgrades accepted
  std::vector<std::string> agents;     // the "agent" field of each accepted hello
  std::vector<ReceivedFrame> frames;   // device states that decoded cleanly, in order
  std::vector<std::string> errors;     // anything that should not happen: bad hello, bad frame
  std::vector<int> agent_close_codes;  // close codes the agent sent, one per closed connection
  std::vector<std::string> agent_close_reasons;  // and their reasons
  int models_sent = 0;
  std::vector<LinkReport> link_reports;  // the agent's, about one a second
};

class FakeStationServer {
 public:
  explicit FakeStationServer(FakeStationBehaviour behaviour = {});
  ~FakeStationServer();

  std::string url() const;  // ws://127.0.0.1:<port>/agent
  unsigned short port() const { return port_; }
  FakeStationRecord record() const;

  struct State;  // shared with the sessions, which may outlive a request

 private:
  void do_accept();

  boost::asio::io_context io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  unsigned short port_ = 0;
  std::shared_ptr<State> state_;
  std::thread thread_;
};

}  // namespace incise::devices::agent::testing
