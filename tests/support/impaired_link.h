#pragma once
// An in-process TCP proxy that impairs a WebSocket link like a slow, lossy network, so the agent's
// haptic loop can be tested at added delay and loss on loopback without tc netem (which needs
// privileges CI may not have). Tests put it between the agent and a server:
//
//   agent --ws--> 127.0.0.1:link.port() --(delay, jitter, loss)--> upstream_host:upstream_port
//
// What it does to the bytes:
// - The HTTP upgrade request and response pass through untouched (each delayed like a frame).
//   If the response is not "101", the rest of that connection is forwarded raw.
// - After the upgrade each direction is cut into WebSocket frames (RFC 6455 section 5.2) and each
//   frame's bytes are forwarded verbatim (never unmasked or changed), delivered at
//   arrival + delay + a uniform 0..jitter, but never before the frame ahead of it: order is kept.
//   The arrival of a frame is when its last byte reached the proxy.
// - A binary data frame (opcode 2, FIN set) is dropped with probability loss. Text,
//   continuation and control frames (close, ping, pong) are never dropped, so what arrives is
//   still a valid WebSocket stream; to the agent this looks like a lossy datagram link for the
//   latest-wins state and force-model messages. TCP itself never loses; it only delays.
// - An end of stream (FIN) is passed on after what was queued ahead of it; a reset or write error
//   closes both sides.
// - Every frame is bounded (kMaxFrameBytes, kMaxHeaderBytes); a larger one closes the connection.
//
// One io thread; timers, no busy waiting. Each connection and direction draws from its own
// generator seeded from (seed, connection number, direction), so which frames are lost is the
// same from run to run for the same traffic.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>

namespace incise::devices::agent::testing {

struct Impairment {
  std::chrono::microseconds delay{0};   // added one way, in each direction (round trip + 2 delay)
  std::chrono::microseconds jitter{0};  // uniform extra 0..jitter per frame; order is kept
  double loss = 0.0;  // probability in [0, 1] that a binary data frame is dropped, each direction
  uint64_t seed = 1;
};

class ImpairedLink {
 public:
  static constexpr std::size_t kMaxHeaderBytes = 16 * 1024;        // HTTP upgrade headers
  static constexpr std::size_t kMaxFrameBytes = 32 * 1024 * 1024;  // one WebSocket frame

  // Listens on 127.0.0.1 at a port the OS picks and connects each accepted client to
  // upstream_host:upstream_port. Throws std::invalid_argument for an impairment out of range
  // (negative delay or jitter, loss outside [0, 1]) and boost::system::system_error if it cannot
  // listen.
  ImpairedLink(std::string upstream_host, uint16_t upstream_port, Impairment impairment = {});
  ~ImpairedLink();  // closes every connection, stops and joins the io thread
  ImpairedLink(const ImpairedLink&) = delete;
  ImpairedLink& operator=(const ImpairedLink&) = delete;

  uint16_t port() const { return port_; }

  // Thread-safe; applies to frames that complete after the call (queued ones keep their time).
  // Throws std::invalid_argument like the constructor.
  void set_impairment(const Impairment& impairment);

  // Resets every open connection at once, both sides (RST, queued bytes discarded), like a pulled
  // cable that the operating systems noticed. Returns when done. New connections are still
  // accepted unless set_refusing(true). Not to be called from the link's own thread.
  void cut();

  // While refusing, each new client is reset right after the accept, before any byte is read.
  void set_refusing(bool refusing);

  struct Stats {
    uint64_t frames_up = 0;     // WebSocket frames seen client -> upstream, dropped ones included
    uint64_t frames_down = 0;   // and upstream -> client
    uint64_t dropped_up = 0;    // binary data frames dropped client -> upstream
    uint64_t dropped_down = 0;  // and upstream -> client
    uint64_t connections = 0;   // clients accepted (refused ones not counted)
  };
  Stats stats() const;

 private:
  struct Shared;     // impairment, counters and flags, shared with the connections
  class Connection;  // one client and its upstream socket

  void do_accept();

  boost::asio::io_context io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  uint16_t port_ = 0;
  std::shared_ptr<Shared> shared_;
  std::vector<std::weak_ptr<Connection>> connections_;  // only touched on the io thread
  std::thread thread_;
};

}  // namespace incise::devices::agent::testing
