// ImpairedLink between a Beast WebSocket client and a Beast echo server (or raw TCP peers where
// the exact bytes matter): frames pass verbatim and in order, delay adds to each direction, loss
// hits only whole binary messages at the configured rate, and ends of stream and cuts reach the
// client.
#include "impaired_link.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <future>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <boost/asio/connect.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

namespace incise::devices::agent::testing {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using error_code = boost::system::error_code;
using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;
using namespace std::chrono_literals;

// Echoes every message back as one frame of the same type.
class EchoServer {
 public:
  EchoServer()
      : acceptor_(io_, tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0)),
        port_(acceptor_.local_endpoint().port()) {
    do_accept();
    thread_ = std::thread([this] { io_.run(); });
  }
  ~EchoServer() {
    io_.stop();
    thread_.join();
  }
  uint16_t port() const { return port_; }

 private:
  class Session : public std::enable_shared_from_this<Session> {
   public:
    explicit Session(tcp::socket socket) : ws_(std::move(socket)) {}
    void run() {
      ws_.auto_fragment(false);
      ws_.read_message_max(64 << 20);
      ws_.async_accept([self = shared_from_this()](error_code ec) {
        if (!ec) self->do_read();
      });
    }

   private:
    void do_read() {
      ws_.async_read(buffer_, [self = shared_from_this()](error_code ec, std::size_t) {
        if (ec) return;
        self->ws_.text(self->ws_.got_text());
        self->ws_.async_write(self->buffer_.data(), [self](error_code ec, std::size_t) {
          if (ec) return;
          self->buffer_.consume(self->buffer_.size());
          self->do_read();
        });
      });
    }
    websocket::stream<beast::tcp_stream> ws_;
    beast::flat_buffer buffer_;
  };

  void do_accept() {
    acceptor_.async_accept(asio::make_strand(io_), [this](error_code ec, tcp::socket socket) {
      if (ec) return;
      std::make_shared<Session>(std::move(socket))->run();
      do_accept();
    });
  }

  asio::io_context io_;
  tcp::acceptor acceptor_;
  uint16_t port_;
  std::thread thread_;
};

// A Beast client whose every asynchronous step has a deadline, so a broken proxy fails a test
// instead of hanging it (a step past its deadline reports beast::error::timeout). Writes are
// synchronous: the messages are small next to the socket buffers, or the peer is reading.
class WsClient {
 public:
  struct Message {
    error_code ec;
    bool binary = false;
    std::string payload;
  };

  error_code connect(uint16_t port, milliseconds timeout = 2s) {
    error_code result;
    ws_.next_layer().async_connect(
        tcp::endpoint(asio::ip::make_address("127.0.0.1"), port), [&](error_code ec) {
          if (ec) {
            result = ec;
            return;
          }
          ws_.async_handshake("127.0.0.1:" + std::to_string(port), "/agent",
                              [&](error_code ec) { result = ec; });
        });
    if (!run(timeout)) result = beast::error::timeout;
    ws_.auto_fragment(false);
    ws_.read_message_max(64 << 20);
    return result;
  }

  void send(bool binary, std::string_view payload) {
    ws_.binary(binary);
    ws_.write(asio::buffer(payload.data(), payload.size()));
  }

  Message receive(milliseconds timeout = 2s) {
    Message message;
    ws_.async_read(buffer_, [&](error_code ec, std::size_t) { message.ec = ec; });
    if (!run(timeout)) message.ec = beast::error::timeout;
    message.binary = ws_.got_binary();
    message.payload = beast::buffers_to_string(buffer_.data());
    buffer_.consume(buffer_.size());
    return message;
  }

  // The close handshake, then Beast waits for the server's end of stream (TCP FIN).
  error_code close(milliseconds timeout = 2s) {
    error_code result;
    ws_.async_close(websocket::close_code::normal, [&](error_code ec) { result = ec; });
    if (!run(timeout)) result = beast::error::timeout;
    return result;
  }

 private:
  // Runs the pending step; false if it was still pending at the deadline (it is then aborted
  // by closing the socket).
  bool run(milliseconds timeout) {
    io_.restart();
    io_.run_for(timeout);
    if (io_.stopped()) return true;
    error_code ignored;
    ws_.next_layer().close(ignored);
    io_.restart();
    io_.run();
    return false;
  }

  asio::io_context io_;
  websocket::stream<tcp::socket> ws_{io_};
  beast::flat_buffer buffer_;
};

// A raw TCP upstream for byte-exact checks: after the request headers it writes `reply` and ends
// its side (FIN), and keeps everything the client sent until the client's end of stream.
class RawUpstream {
 public:
  explicit RawUpstream(std::string reply)
      : acceptor_(io_, tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0)),
        socket_(io_),
        reply_(std::move(reply)) {
    acceptor_.async_accept(socket_, [this](error_code ec) {
      if (!ec) do_read();
    });
    thread_ = std::thread([this] { io_.run(); });
  }
  ~RawUpstream() {
    io_.stop();
    thread_.join();
  }
  uint16_t port() const { return acceptor_.local_endpoint().port(); }

  // Everything the client sent, once it ended its stream; nullopt if that did not happen in time.
  std::optional<std::string> received(milliseconds timeout) {
    if (result_.wait_for(timeout) != std::future_status::ready) return std::nullopt;
    return result_.get();
  }

 private:
  void do_read() {
    socket_.async_read_some(asio::buffer(chunk_), [this](error_code ec, std::size_t n) {
      if (ec) {
        done_.set_value(ec == asio::error::eof ? received_ : "read error: " + ec.message());
        return;
      }
      received_.append(chunk_.data(), n);
      if (!replied_ && received_.find("\r\n\r\n") != std::string::npos) {
        replied_ = true;
        asio::async_write(socket_, asio::buffer(reply_), [this](error_code ec, std::size_t) {
          if (!ec) socket_.shutdown(tcp::socket::shutdown_send, ec);
        });
      }
      do_read();
    });
  }

  asio::io_context io_;
  tcp::acceptor acceptor_;
  tcp::socket socket_;
  std::string reply_;
  std::string received_;
  std::array<char, 4096> chunk_{};
  bool replied_ = false;
  std::promise<std::string> done_;
  std::future<std::string> result_ = done_.get_future();
  std::thread thread_;
};

// Reads until the peer's end of stream; nullopt on timeout or an error other than EOF.
std::optional<std::string> read_to_end(asio::io_context& io, tcp::socket& socket,
                                       milliseconds timeout) {
  std::string data;
  error_code result;
  bool done = false;
  asio::async_read(socket, asio::dynamic_buffer(data), [&](error_code ec, std::size_t) {
    result = ec;
    done = true;
  });
  io.restart();
  io.run_for(timeout);
  if (!done) {
    socket.close();
    io.restart();
    io.run();
    return std::nullopt;
  }
  if (result != asio::error::eof) return std::nullopt;
  return data;
}

// A WebSocket frame built by hand (RFC 6455 section 5.2) with the length in the given form:
// 7 (payload <= 125), 16 or 64 bits; masked when a key is given.
std::string ws_frame(uint8_t first_byte, std::string_view payload, int length_bits,
                     std::optional<std::array<uint8_t, 4>> mask = std::nullopt) {
  std::string frame(1, static_cast<char>(first_byte));
  const uint8_t mask_bit = mask ? 0x80 : 0x00;
  const uint64_t n = payload.size();
  if (length_bits == 7) {
    frame += static_cast<char>(mask_bit | n);
  } else {
    const int bytes = length_bits / 8;
    frame += static_cast<char>(mask_bit | (bytes == 2 ? 126 : 127));
    for (int i = bytes - 1; i >= 0; --i)
      frame += static_cast<char>((n >> (8 * i)) & 0xFF);
  }
  if (!mask) return frame + std::string(payload);
  for (uint8_t k : *mask)
    frame += static_cast<char>(k);
  for (std::size_t i = 0; i < n; ++i)
    frame += static_cast<char>(payload[i] ^ (*mask)[i % 4]);
  return frame;
}

std::string patterned(std::size_t size, int salt) {
  std::string s(size, '\0');
  for (std::size_t i = 0; i < size; ++i)
    s[i] = static_cast<char>((i * 131 + salt * 7) & 0xFF);
  return s;
}

std::string indexed(uint32_t index) {
  std::string payload = patterned(20, static_cast<int>(index));
  std::memcpy(payload.data(), &index, sizeof index);
  return payload;
}

uint32_t index_of(const std::string& payload) {
  uint32_t index = 0;
  std::memcpy(&index, payload.data(), sizeof index);
  return index;
}

milliseconds median(std::vector<Clock::duration> durations) {
  std::sort(durations.begin(), durations.end());
  return std::chrono::duration_cast<milliseconds>(durations[durations.size() / 2]);
}

TEST(ImpairedLink, PassesFramesThroughByteExactAndInOrder) {
  EchoServer server;
  ImpairedLink link("127.0.0.1", server.port());
  WsClient client;
  ASSERT_FALSE(client.connect(link.port()));

  std::vector<std::pair<bool, std::string>> sent;
  for (int i = 0; i < 60; ++i) {
    if (i % 5 == 4) {
      sent.emplace_back(false, "text message " + std::to_string(i));
    } else {
      sent.emplace_back(true, patterned(static_cast<std::size_t>(i * 37 % 300), i));
    }
  }
  for (const auto& [binary, payload] : sent)
    client.send(binary, payload);
  for (const auto& [binary, payload] : sent) {
    const WsClient::Message m = client.receive();
    ASSERT_FALSE(m.ec) << m.ec.message();
    EXPECT_EQ(m.binary, binary);
    EXPECT_EQ(m.payload, payload);
  }
  ImpairedLink::Stats s = link.stats();
  EXPECT_EQ(s.frames_up, sent.size());
  EXPECT_EQ(s.frames_down, sent.size());
  EXPECT_EQ(s.dropped_up + s.dropped_down, 0u);
  EXPECT_EQ(s.connections, 1u);

  // The close handshake and both ends of stream pass too (Beast's close waits for the EOF).
  EXPECT_FALSE(client.close());
  s = link.stats();
  EXPECT_EQ(s.frames_up, sent.size() + 1);
  EXPECT_EQ(s.frames_down, sent.size() + 1);
}

TEST(ImpairedLink, LargeFramesWithExtendedLengthsPassIntact) {
  EchoServer server;
  ImpairedLink link("127.0.0.1", server.port(), {.delay = 2ms});
  WsClient client;
  ASSERT_FALSE(client.connect(link.port()));
  // 7-bit, 16-bit (126..65535) and 64-bit lengths; one frame each way per message.
  const std::vector<std::size_t> sizes = {125, 126, 65535, 65536, (1u << 20) + 3};
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    const std::string payload = patterned(sizes[i], static_cast<int>(i));
    client.send(true, payload);
    const WsClient::Message m = client.receive();
    ASSERT_FALSE(m.ec) << m.ec.message();
    EXPECT_TRUE(m.payload == payload) << "size " << sizes[i];
  }
  EXPECT_EQ(link.stats().frames_up, sizes.size());
  EXPECT_EQ(link.stats().frames_down, sizes.size());
}

// Hand-made frames in every length form, masked client -> server, fed to the proxy a few bytes at
// a time: the upstream must get the very bytes sent, minus the dropped binary messages.
class RawFrames : public ::testing::TestWithParam<double> {};

TEST_P(RawFrames, AreForwardedVerbatimAcrossSplitReads) {
  const double loss = GetParam();  // 0 keeps every frame, 1 drops every binary message
  const std::array<uint8_t, 4> key = {0x37, 0xFA, 0x21, 0x3D};
  const std::string request =
      "GET /agent HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
      "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n";
  const std::vector<std::pair<std::string, bool>> up = {
      // frame, is a whole binary message
      {ws_frame(0x82, patterned(40, 1), 7, key), true},
      {ws_frame(0x81, "hello over a 16-bit length", 16, key), false},
      {ws_frame(0x82, patterned(300, 2), 16, key), true},
      {ws_frame(0x82, patterned(70000, 3), 64, key), true},
      {ws_frame(0x89, "", 7, key), false},                 // ping
      {ws_frame(0x02, patterned(10, 4), 7, key), false},   // first fragment of a binary message
      {ws_frame(0x80, patterned(10, 5), 64, key), false},  // its last fragment
      {ws_frame(0x82, "", 7, key), true},
      {ws_frame(0x88, "\x03\xe8", 7, key), false},  // close 1000
  };
  const std::string response =
      "HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
      "Sec-WebSocket-Accept: s3pPLMBiTxaQ9kYGzzhZRbK+xOo=\r\n\r\n";
  const std::vector<std::pair<std::string, bool>> down = {
      {ws_frame(0x82, patterned(137, 6), 16), true},
      {ws_frame(0x8A, "pong", 7), false},
      {ws_frame(0x82, patterned(66000, 7), 64), true},
      {ws_frame(0x81, "{\"type\":\"welcome\"}", 7), false},
      {ws_frame(0x88, "\x03\xe8", 7), false},
  };
  std::string sent = request, expected_up = request, reply = response, expected_down = response;
  for (const auto& [frame, droppable] : up) {
    sent += frame;
    if (!(droppable && loss == 1.0)) expected_up += frame;
  }
  for (const auto& [frame, droppable] : down) {
    reply += frame;
    if (!(droppable && loss == 1.0)) expected_down += frame;
  }

  RawUpstream upstream(reply);
  ImpairedLink link("127.0.0.1", upstream.port(), {.loss = loss});
  asio::io_context io;
  tcp::socket client(io);
  client.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), link.port()));
  client.set_option(tcp::no_delay(true));
  // Pieces of 1..7 bytes with pauses, so that headers and lengths straddle the proxy's reads.
  std::size_t at = 0;
  for (int piece = 0; at < sent.size(); ++piece) {
    const std::size_t n = std::min(sent.size() - at, at < 800 ? 1 + piece % 7 : std::size_t{4096});
    asio::write(client, asio::buffer(sent.data() + at, n));
    at += n;
    if (at < 800) std::this_thread::sleep_for(100us);
  }
  client.shutdown(tcp::socket::shutdown_send);

  const std::optional<std::string> got_down = read_to_end(io, client, 3000ms);
  const std::optional<std::string> got_up = upstream.received(3000ms);
  ASSERT_TRUE(got_down && got_up);
  EXPECT_TRUE(*got_up == expected_up)
      << got_up->size() << " bytes, expected " << expected_up.size();
  EXPECT_TRUE(*got_down == expected_down)
      << got_down->size() << " bytes, expected " << expected_down.size();
  const ImpairedLink::Stats s = link.stats();
  EXPECT_EQ(s.frames_up, up.size());
  EXPECT_EQ(s.frames_down, down.size());
  EXPECT_EQ(s.dropped_up, loss == 1.0 ? 4u : 0u);
  EXPECT_EQ(s.dropped_down, loss == 1.0 ? 2u : 0u);
}

INSTANTIATE_TEST_SUITE_P(ImpairedLink, RawFrames, ::testing::Values(0.0, 1.0));

class Delay : public ::testing::TestWithParam<int> {};

TEST_P(Delay, AddsToEachDirectionOfTheRoundTrip) {
  const milliseconds delay(GetParam());
  constexpr milliseconds kMargin = 30ms;  // scheduling on a shared, busy machine
  EchoServer server;
  ImpairedLink link("127.0.0.1", server.port(), {.delay = delay});
  WsClient client;
  ASSERT_FALSE(client.connect(link.port()));

  std::vector<Clock::duration> round_trips;
  for (uint32_t i = 0; i < 5; ++i) {
    const Clock::time_point start = Clock::now();
    client.send(true, indexed(i));
    const WsClient::Message m = client.receive();
    round_trips.push_back(Clock::now() - start);
    ASSERT_FALSE(m.ec) << m.ec.message();
    EXPECT_EQ(index_of(m.payload), i);
    EXPECT_GE(round_trips.back(), 2 * delay);  // timers never fire early
  }
  EXPECT_LT(median(round_trips), 2 * delay + kMargin);
  RecordProperty("median_round_trip_ms", static_cast<int>(median(round_trips).count()));

  // A new impairment applies to the frames that arrive after it.
  link.set_impairment({});
  round_trips.clear();
  for (uint32_t i = 0; i < 5; ++i) {
    const Clock::time_point start = Clock::now();
    client.send(true, indexed(i));
    ASSERT_FALSE(client.receive().ec);
    round_trips.push_back(Clock::now() - start);
  }
  EXPECT_LT(*std::min_element(round_trips.begin(), round_trips.end()), delay);
}

INSTANTIATE_TEST_SUITE_P(ImpairedLink, Delay, ::testing::Values(10, 50));

TEST(ImpairedLink, JitterNeverReorders) {
  constexpr milliseconds kDelay = 5ms, kJitter = 15ms;
  EchoServer server;
  ImpairedLink link("127.0.0.1", server.port(), {.delay = kDelay, .jitter = kJitter});
  WsClient client;
  ASSERT_FALSE(client.connect(link.port()));

  // Frames 1 ms apart with up to 15 ms of jitter each: independent delays would reorder them.
  constexpr uint32_t kFrames = 150;
  for (uint32_t i = 0; i < kFrames; ++i) {
    client.send(true, indexed(i));
    std::this_thread::sleep_for(1ms);
  }
  for (uint32_t i = 0; i < kFrames; ++i) {
    const WsClient::Message m = client.receive();
    ASSERT_FALSE(m.ec) << m.ec.message();
    ASSERT_EQ(index_of(m.payload), i);
  }

  std::vector<Clock::duration> round_trips;
  for (uint32_t i = 0; i < 7; ++i) {
    const Clock::time_point start = Clock::now();
    client.send(true, indexed(i));
    ASSERT_FALSE(client.receive().ec);
    round_trips.push_back(Clock::now() - start);
    EXPECT_GE(round_trips.back(), 2 * kDelay);
  }
  EXPECT_LT(median(round_trips), 2 * (kDelay + kJitter) + 30ms);
}

// Sends `binaries` numbered binary messages with a text message after every tenth and a final
// "end" text, and returns the indices of the binary echoes that came back before "end".
struct LossRun {
  std::vector<uint32_t> received;
  int texts_received = 0;
  ImpairedLink::Stats stats;
};

LossRun run_lossy(const Impairment& impairment, uint32_t binaries) {
  EchoServer server;
  ImpairedLink link("127.0.0.1", server.port(), impairment);
  WsClient client;
  LossRun run;
  if (const error_code ec = client.connect(link.port())) {
    ADD_FAILURE() << "connect: " << ec.message();
    return run;
  }
  for (uint32_t i = 0; i < binaries; ++i) {
    client.send(true, indexed(i));
    if (i % 10 == 9) client.send(false, "text " + std::to_string(i));
  }
  client.send(false, "end");
  for (;;) {
    const WsClient::Message m = client.receive();
    if (m.ec) {
      ADD_FAILURE() << "receive: " << m.ec.message();
      break;
    }
    if (!m.binary && m.payload == "end") break;
    if (m.binary) {
      run.received.push_back(index_of(m.payload));
    } else {
      // Text k follows binary k and comes back after it, before binary k + 1.
      const uint32_t k = 10 * static_cast<uint32_t>(run.texts_received) + 9;
      EXPECT_EQ(m.payload, "text " + std::to_string(k));
      if (!run.received.empty()) {
        EXPECT_LE(run.received.back(), k);
      }
      ++run.texts_received;
    }
  }
  run.stats = link.stats();
  return run;
}

TEST(ImpairedLink, LossDropsOnlyBinaryMessagesAtTheConfiguredRate) {
  constexpr uint32_t kBinaries = 2000;
  constexpr uint32_t kTexts = kBinaries / 10 + 1;  // with "end"
  constexpr double kLoss = 0.3;
  const LossRun run = run_lossy({.loss = kLoss, .seed = 42}, kBinaries);
  const ImpairedLink::Stats& s = run.stats;

  EXPECT_EQ(run.texts_received, static_cast<int>(kTexts) - 1);
  EXPECT_EQ(s.frames_up, kBinaries + kTexts);
  EXPECT_EQ(s.frames_down, kBinaries - s.dropped_up + kTexts);
  EXPECT_EQ(run.received.size(), kBinaries - s.dropped_up - s.dropped_down);
  EXPECT_TRUE(std::is_sorted(run.received.begin(), run.received.end()));
  EXPECT_EQ(std::adjacent_find(run.received.begin(), run.received.end()), run.received.end());

  // Each direction's drops are Binomial(n, loss): within 5 standard deviations.
  const auto check_rate = [&](uint64_t dropped, uint64_t n, const char* direction) {
    const double sigma = std::sqrt(kLoss * (1 - kLoss) / static_cast<double>(n));
    EXPECT_NEAR(static_cast<double>(dropped) / static_cast<double>(n), kLoss, 5 * sigma)
        << direction;
  };
  check_rate(s.dropped_up, kBinaries, "up");
  check_rate(s.dropped_down, kBinaries - s.dropped_up, "down");
  RecordProperty("dropped_up", static_cast<int>(s.dropped_up));
  RecordProperty("dropped_down", static_cast<int>(s.dropped_down));
}

TEST(ImpairedLink, LossIsReproducibleForASeed) {
  const LossRun a = run_lossy({.loss = 0.5, .seed = 9}, 300);
  const LossRun b = run_lossy({.loss = 0.5, .seed = 9}, 300);
  const LossRun c = run_lossy({.loss = 0.5, .seed = 10}, 300);
  EXPECT_FALSE(a.received.empty());
  EXPECT_EQ(a.received, b.received);
  EXPECT_NE(a.received, c.received);
}

TEST(ImpairedLink, DeliversWhatWasQueuedBeforePassingOnAClose) {
  constexpr milliseconds kDelay = 30ms;
  std::string reply = "HTTP/1.1 101 Switching Protocols\r\n\r\n";
  for (int i = 0; i < 20; ++i)
    reply += ws_frame(0x82, patterned(100, i), 7);
  RawUpstream upstream(reply);  // closes its side right after the reply
  ImpairedLink link("127.0.0.1", upstream.port(), {.delay = kDelay});
  asio::io_context io;
  tcp::socket client(io);
  client.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), link.port()));
  const Clock::time_point start = Clock::now();
  asio::write(client, asio::buffer(std::string_view("GET / HTTP/1.1\r\n\r\n")));
  const std::optional<std::string> got = read_to_end(io, client, 2000ms);
  const Clock::duration elapsed = Clock::now() - start;
  ASSERT_TRUE(got) << "no orderly end of stream";
  EXPECT_TRUE(*got == reply) << got->size() << " bytes of " << reply.size();
  EXPECT_GE(elapsed, 2 * kDelay);
  EXPECT_EQ(link.stats().frames_down, 20u);
}

TEST(ImpairedLink, CutResetsOpenConnectionsAndRefusingRefusesNewOnes) {
  EchoServer server;
  ImpairedLink link("127.0.0.1", server.port());
  WsClient first;
  ASSERT_FALSE(first.connect(link.port()));
  first.send(true, indexed(1));
  ASSERT_FALSE(first.receive().ec);

  // The client is blocked in a read when the cable is pulled.
  Clock::time_point cut_at;
  std::thread puller([&] {
    std::this_thread::sleep_for(100ms);
    cut_at = Clock::now();
    link.cut();
  });
  const WsClient::Message m = first.receive(3000ms);
  const Clock::time_point noticed = Clock::now();
  puller.join();
  EXPECT_EQ(m.ec, asio::error::connection_reset) << m.ec.message();  // not a polite FIN
  EXPECT_LT(noticed - cut_at, 500ms);

  WsClient second;  // still accepting
  ASSERT_FALSE(second.connect(link.port()));
  second.send(true, indexed(2));
  EXPECT_EQ(index_of(second.receive().payload), 2u);

  link.set_refusing(true);
  WsClient refused;
  EXPECT_TRUE(refused.connect(link.port()));
  link.set_refusing(false);
  WsClient third;
  EXPECT_FALSE(third.connect(link.port()));
  EXPECT_EQ(link.stats().connections, 3u);
}

TEST(ImpairedLink, UnreachableUpstreamClosesTheClient) {
  uint16_t dead_port = 0;
  {
    asio::io_context io;
    tcp::acceptor probe(io, tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
    dead_port = probe.local_endpoint().port();
  }  // nothing listens there any more
  ImpairedLink link("127.0.0.1", dead_port);
  WsClient client;
  const error_code ec = client.connect(link.port(), 2000ms);
  EXPECT_TRUE(ec);
  EXPECT_NE(ec, beast::error::timeout);
}

TEST(ImpairedLink, RejectsImpairmentsOutOfRange) {
  EXPECT_THROW(ImpairedLink("127.0.0.1", 1, {.loss = 1.5}), std::invalid_argument);
  EXPECT_THROW(ImpairedLink("127.0.0.1", 1, {.delay = -1ms}), std::invalid_argument);
  ImpairedLink link("127.0.0.1", 1);
  EXPECT_THROW(link.set_impairment({.jitter = -1ms}), std::invalid_argument);
  EXPECT_THROW(link.set_impairment({.loss = std::nan("")}), std::invalid_argument);
}

}  // namespace
}  // namespace incise::devices::agent::testing
