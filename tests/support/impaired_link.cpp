#include "impaired_link.h"

#include <algorithm>
#include <array>
#include <deque>
#include <future>
#include <random>
#include <span>
#include <stdexcept>
#include <string_view>

#include <boost/asio/connect.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>

namespace incise::devices::agent::testing {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;
using Clock = std::chrono::steady_clock;
using error_code = boost::system::error_code;

namespace {

constexpr std::size_t kReadChunk = 64 * 1024;
// Past this many bytes queued in one direction the proxy stops reading that direction's source
// until the queue drains, so a flood is held back by TCP instead of growing memory.
constexpr std::size_t kMaxQueuedBytes = 64 * 1024 * 1024;
constexpr std::size_t kMaxGather = 64;  // frames handed to one write

enum class Extent { need_more, complete, too_big };

// The size in bytes of the WebSocket frame that starts at bytes[0], header included (RFC 6455
// section 5.2): 2 bytes, then a 16-bit (length code 126) or 64-bit (127) big-endian payload
// length, then a 4-byte masking key if the mask bit is set, then the payload.
Extent frame_size(std::span<const uint8_t> bytes, std::size_t max_size, std::size_t& size) {
  if (bytes.size() < 2) return Extent::need_more;
  uint64_t length = bytes[1] & 0x7Fu;
  std::size_t header = 2;
  if (length >= 126) {
    const std::size_t length_bytes = length == 126 ? 2 : 8;
    header += length_bytes;
    if (bytes.size() < header) return Extent::need_more;
    length = 0;
    for (std::size_t i = 0; i < length_bytes; ++i)
      length = (length << 8) | bytes[2 + i];
  }
  if (bytes[1] & 0x80u) header += 4;
  // Also rejects 64-bit lengths with the most significant bit set, which RFC 6455 forbids.
  if (length > max_size - header) return Extent::too_big;
  size = header + static_cast<std::size_t>(length);
  return bytes.size() >= size ? Extent::complete : Extent::need_more;
}

// Only a whole binary message may be lost: dropping a text frame, a fragment or a control frame
// would break the WebSocket stream rather than emulate a lost datagram.
bool is_droppable(uint8_t first_byte) {
  return (first_byte & 0x8Fu) == 0x82u;
}  // FIN, opcode 2

uint64_t splitmix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

void validate(const Impairment& impairment) {
  if (impairment.delay.count() < 0) throw std::invalid_argument("ImpairedLink: delay < 0");
  if (impairment.jitter.count() < 0) throw std::invalid_argument("ImpairedLink: jitter < 0");
  if (!(impairment.loss >= 0.0 && impairment.loss <= 1.0)) {
    throw std::invalid_argument("ImpairedLink: loss outside [0, 1]");
  }
}

}  // namespace

struct ImpairedLink::Shared {
  std::string upstream_host;
  uint16_t upstream_port = 0;
  std::atomic<bool> refusing{false};
  std::array<std::atomic<uint64_t>, 2> frames{};  // indexed by direction: 0 up, 1 down
  std::array<std::atomic<uint64_t>, 2> dropped{};
  std::atomic<uint64_t> connections{0};

  Impairment impairment() const {
    std::lock_guard lock(mutex_);
    return impairment_;
  }
  void set_impairment(const Impairment& impairment) {
    std::lock_guard lock(mutex_);
    impairment_ = impairment;
  }

 private:
  mutable std::mutex mutex_;
  Impairment impairment_;
};

class ImpairedLink::Connection : public std::enable_shared_from_this<Connection> {
 public:
  Connection(tcp::socket client, std::shared_ptr<Shared> shared, uint64_t number)
      : shared_(std::move(shared)),
        number_(number),
        client_(std::move(client)),
        upstream_(client_.get_executor()),
        resolver_(client_.get_executor()),
        up_(kUp, client_, upstream_),
        down_(kDown, upstream_, client_) {}

  void start() {
    resolver_.async_resolve(
        shared_->upstream_host, std::to_string(shared_->upstream_port),
        [self = shared_from_this()](error_code ec, tcp::resolver::results_type results) {
          if (self->closed_) return;
          if (ec) return self->close(false);
          asio::async_connect(
              self->upstream_, results,
              [self](error_code ec, const tcp::endpoint&) { self->on_connect(ec); });
        });
  }

  // Closes both sockets now. With reset, as an RST (SO_LINGER 0) that discards unsent bytes.
  void close(bool reset) {
    if (closed_) return;
    closed_ = true;
    error_code ignored;
    for (tcp::socket* socket : {&client_, &upstream_}) {
      if (reset) socket->set_option(asio::socket_base::linger(true, 0), ignored);
      socket->close(ignored);
    }
    resolver_.cancel();
    up_.timer.cancel();
    down_.timer.cancel();
  }

 private:
  enum Direction { kUp = 0, kDown = 1 };
  enum class Phase { headers, frames, raw };

  struct Queued {
    Clock::time_point due;
    // One allocation per frame: this is a test proxy, not a hot loop, and it keeps dropping and
    // scheduling whole frames simple.
    std::vector<uint8_t> bytes;
  };

  // One direction: reads src, cuts the bytes into units (the upgrade headers, then frames),
  // schedules each unit and writes it to dst when due.
  struct Pipe {
    Pipe(Direction d, tcp::socket& from, tcp::socket& to)
        : direction(d), src(from), dst(to), timer(from.get_executor()) {}

    Direction direction;
    tcp::socket& src;
    tcp::socket& dst;
    asio::steady_timer timer;
    Phase phase = Phase::headers;
    std::array<uint8_t, kReadChunk> chunk{};
    std::vector<uint8_t> pending;  // read but not yet a whole unit, from pending_begin on
    std::size_t pending_begin = 0;
    std::deque<Queued> queue;  // due times never decrease
    std::size_t queued_bytes = 0;
    Clock::time_point last_due{};
    std::vector<asio::const_buffer> out;  // the write in flight: the first out.size() of queue
    std::mt19937_64 rng;
    uint64_t seeded_with = 0;
    bool seeded = false;
    bool reading_paused = false;
    bool writing = false;
    bool waiting = false;
    bool src_ended = false;
    bool src_failed = false;  // ended by an error, not an orderly FIN
    bool finished = false;
  };

  void on_connect(error_code ec) {
    if (closed_) return;
    if (ec) return close(false);
    // Nagle's algorithm would hold small frames back for up to a delayed ACK (~40 ms).
    error_code ignored;
    client_.set_option(tcp::no_delay(true), ignored);
    upstream_.set_option(tcp::no_delay(true), ignored);
    do_read(up_);
    do_read(down_);
  }

  void do_read(Pipe& p) {
    p.src.async_read_some(
        asio::buffer(p.chunk),
        [self = shared_from_this(), &p](error_code ec, std::size_t n) { self->on_read(p, ec, n); });
  }

  void on_read(Pipe& p, error_code ec, std::size_t n) {
    if (closed_) return;
    if (ec) {
      p.src_ended = true;
      p.src_failed = ec != asio::error::eof;
      return deliver(p);
    }
    const Clock::time_point arrival = Clock::now();
    p.pending.insert(p.pending.end(), p.chunk.begin(), p.chunk.begin() + n);
    if (!cut_units(p, arrival)) return close(false);
    deliver(p);
    if (p.queued_bytes > kMaxQueuedBytes) {
      p.reading_paused = true;
      return;
    }
    do_read(p);
  }

  // Moves every whole unit out of p.pending into p.queue (or drops it). False for input that
  // breaks a bound.
  bool cut_units(Pipe& p, Clock::time_point arrival) {
    const Impairment impairment = shared_->impairment();
    if (!p.seeded || p.seeded_with != impairment.seed) {
      p.rng.seed(splitmix64(impairment.seed ^ splitmix64(2 * number_ + p.direction)));
      p.seeded_with = impairment.seed;
      p.seeded = true;
    }
    for (;;) {
      const std::span<const uint8_t> rest(p.pending.data() + p.pending_begin,
                                          p.pending.size() - p.pending_begin);
      if (rest.empty()) break;
      std::size_t size = 0;
      if (p.phase == Phase::raw) {
        size = rest.size();
      } else if (p.phase == Phase::headers) {
        const std::string_view text(reinterpret_cast<const char*>(rest.data()), rest.size());
        const std::size_t end = text.find("\r\n\r\n");
        if (end == std::string_view::npos) {
          if (rest.size() > ImpairedLink::kMaxHeaderBytes) return false;
          break;
        }
        size = end + 4;
        p.phase = Phase::frames;
        // A refused upgrade (anything but 101) is followed by an HTTP body or another request,
        // not frames: forward the rest of the connection as it comes.
        if (p.direction == kDown && !text.starts_with("HTTP/1.1 101 ")) {
          down_.phase = Phase::raw;
          up_.phase = Phase::raw;
        }
      } else {
        const Extent extent = frame_size(rest, ImpairedLink::kMaxFrameBytes, size);
        if (extent == Extent::too_big) return false;
        if (extent == Extent::need_more) break;
        shared_->frames[p.direction].fetch_add(1, std::memory_order_relaxed);
        if (is_droppable(rest[0]) && uniform(p) < impairment.loss) {
          shared_->dropped[p.direction].fetch_add(1, std::memory_order_relaxed);
          p.pending_begin += size;
          continue;
        }
      }
      enqueue(p, rest.first(size), arrival, impairment);
      p.pending_begin += size;
    }
    if (p.pending_begin == p.pending.size()) {
      p.pending.clear();
      p.pending_begin = 0;
    } else if (p.pending_begin > p.pending.size() / 2) {
      p.pending.erase(p.pending.begin(), p.pending.begin() + p.pending_begin);
      p.pending_begin = 0;
    }
    return true;
  }

  static double uniform(Pipe& p) { return static_cast<double>(p.rng() >> 11) * 0x1.0p-53; }

  void enqueue(Pipe& p, std::span<const uint8_t> bytes, Clock::time_point arrival,
               const Impairment& impairment) {
    Clock::time_point due = arrival + impairment.delay;
    if (impairment.jitter.count() > 0) {
      const std::chrono::duration<double, std::micro> extra(
          uniform(p) * static_cast<double>(impairment.jitter.count()));
      due += std::chrono::duration_cast<Clock::duration>(extra);
    }
    // Never overtake the frame ahead: a stream link delays, it does not reorder.
    due = std::max(due, p.last_due);
    p.last_due = due;
    p.queue.push_back({due, std::vector<uint8_t>(bytes.begin(), bytes.end())});
    p.queued_bytes += bytes.size();
  }

  // Writes what is due, or waits for the first queued unit's time; passes on the end of src
  // once the queue is empty.
  void deliver(Pipe& p) {
    if (closed_ || p.writing || p.waiting) return;
    if (p.queue.empty()) {
      if (p.src_ended) finish(p);
      return;
    }
    const Clock::time_point now = Clock::now();
    if (p.queue.front().due > now) {
      p.waiting = true;
      p.timer.expires_at(p.queue.front().due);
      p.timer.async_wait([self = shared_from_this(), &p](error_code) {
        p.waiting = false;
        self->deliver(p);
      });
      return;
    }
    p.out.clear();
    for (const Queued& q : p.queue) {
      if (q.due > now || p.out.size() == kMaxGather) break;
      p.out.push_back(asio::buffer(q.bytes));
    }
    p.writing = true;
    asio::async_write(p.dst, p.out, [self = shared_from_this(), &p](error_code ec, std::size_t) {
      self->on_written(p, ec);
    });
  }

  void on_written(Pipe& p, error_code ec) {
    p.writing = false;
    if (closed_) return;
    if (ec) return close(false);
    for (std::size_t i = 0; i < p.out.size(); ++i) {
      p.queued_bytes -= p.queue.front().bytes.size();
      p.queue.pop_front();
    }
    p.out.clear();
    if (p.reading_paused && p.queued_bytes <= kMaxQueuedBytes / 2) {
      p.reading_paused = false;
      do_read(p);
    }
    deliver(p);
  }

  // src ended and everything read before its end was delivered: pass the FIN on (half close),
  // or close both sides if src failed. Both directions finished closes the connection.
  void finish(Pipe& p) {
    if (p.finished) return;
    p.finished = true;
    if (p.src_failed) return close(false);
    error_code ignored;
    p.dst.shutdown(tcp::socket::shutdown_send, ignored);
    if (up_.finished && down_.finished) close(false);
  }

  std::shared_ptr<Shared> shared_;
  uint64_t number_;
  tcp::socket client_;
  tcp::socket upstream_;
  tcp::resolver resolver_;
  Pipe up_;
  Pipe down_;
  bool closed_ = false;
};

ImpairedLink::ImpairedLink(std::string upstream_host, uint16_t upstream_port, Impairment impairment)
    : acceptor_(io_, tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0)),
      port_(acceptor_.local_endpoint().port()),
      shared_(std::make_shared<Shared>()) {
  validate(impairment);
  shared_->upstream_host = std::move(upstream_host);
  shared_->upstream_port = upstream_port;
  shared_->set_impairment(impairment);
  do_accept();
  thread_ = std::thread([this] { io_.run(); });
}

ImpairedLink::~ImpairedLink() {
  // Close politely (FIN) so that peers still running see an end of stream, then stop.
  std::promise<void> closed;
  asio::post(io_, [this, &closed] {
    error_code ignored;
    acceptor_.close(ignored);
    for (const std::weak_ptr<Connection>& weak : connections_) {
      if (const auto connection = weak.lock()) connection->close(false);
    }
    closed.set_value();
  });
  closed.get_future().wait();
  io_.stop();
  thread_.join();
}

void ImpairedLink::set_impairment(const Impairment& impairment) {
  validate(impairment);
  shared_->set_impairment(impairment);
}

void ImpairedLink::cut() {
  std::promise<void> done;
  asio::post(io_, [this, &done] {
    for (const std::weak_ptr<Connection>& weak : connections_) {
      if (const auto connection = weak.lock()) connection->close(true);
    }
    connections_.clear();
    done.set_value();
  });
  done.get_future().wait();
}

void ImpairedLink::set_refusing(bool refusing) {
  shared_->refusing = refusing;
}

ImpairedLink::Stats ImpairedLink::stats() const {
  Stats s;
  s.frames_up = shared_->frames[0].load();
  s.frames_down = shared_->frames[1].load();
  s.dropped_up = shared_->dropped[0].load();
  s.dropped_down = shared_->dropped[1].load();
  s.connections = shared_->connections.load();
  return s;
}

void ImpairedLink::do_accept() {
  acceptor_.async_accept(io_, [this](error_code ec, tcp::socket socket) {
    if (ec) return;  // the acceptor was closed
    if (shared_->refusing) {
      error_code ignored;
      socket.set_option(asio::socket_base::linger(true, 0), ignored);
      socket.close(ignored);
    } else {
      const uint64_t number = ++shared_->connections;
      std::erase_if(connections_, [](const std::weak_ptr<Connection>& c) { return c.expired(); });
      auto connection = std::make_shared<Connection>(std::move(socket), shared_, number);
      connections_.push_back(connection);
      connection->start();
    }
    do_accept();
  });
}

}  // namespace incise::devices::agent::testing
