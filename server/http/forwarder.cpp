#include "server/http/forwarder.h"

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>

#include <array>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <memory>

#include "server/api/router.h"
#include "server/http/http_session.h"

namespace incise::server {

namespace beast = boost::beast;
namespace net = boost::asio;
using tcp = net::ip::tcp;

namespace {
constexpr auto kConnectTimeout = std::chrono::seconds(3);
constexpr auto kWriteTimeout = std::chrono::seconds(30);
// The owner answers from its memory or its database; a review of a long session is the slowest.
constexpr auto kAnswerTimeout = std::chrono::seconds(120);
constexpr std::uint64_t kAnswerLimit = 256ull << 20;

// "host:port" or "[v6]:port" -> host (without brackets), port. The address was checked when the
// node registered it (server_options.h, is_node_address).
std::pair<std::string, std::string> split_address(const std::string& address) {
  const auto colon = address.rfind(':');
  std::string host = address.substr(0, colon);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') {
    host = host.substr(1, host.size() - 2);
  }
  return {host, colon == std::string::npos ? "" : address.substr(colon + 1)};
}

void mark_forwarded(Request& request, const std::string& self_node) {
  request.set(kForwardedByHeader, self_node);
  request.keep_alive(false);  // one request per connection to the owner
}

std::string unreachable(const ForwardTarget& to, const beast::error_code& ec) {
  return "node " + to.node_id + ", which runs this, does not answer (" + ec.message() +
         "); try again in a moment";
}

void keep_alive(tcp::socket& socket) {
  boost::system::error_code ignored;
  socket.set_option(tcp::socket::keep_alive(true), ignored);
  const int fd = socket.native_handle();
  const int idle_s = 10, interval_s = 5, probes = 3;
  setsockopt(fd, IPPROTO_TCP, TCP_KEEPIDLE, &idle_s, sizeof idle_s);
  setsockopt(fd, IPPROTO_TCP, TCP_KEEPINTVL, &interval_s, sizeof interval_s);
  setsockopt(fd, IPPROTO_TCP, TCP_KEEPCNT, &probes, sizeof probes);
}

// What both kinds share: reaching the owner.
class Upstream {
 public:
  Upstream(net::any_io_executor executor, ForwardTarget to)
      : resolver_(executor), stream_(executor), to_(std::move(to)) {}

  template <class Handler>
  void connect(Handler&& on_connected) {
    const auto [host, port] = split_address(to_.address);
    resolver_.async_resolve(host, port,
                            [this, on_connected = std::forward<Handler>(on_connected)](
                                beast::error_code ec, tcp::resolver::results_type results) mutable {
                              if (ec) return on_connected(ec);
                              stream_.expires_after(kConnectTimeout);
                              stream_.async_connect(
                                  results, [on_connected = std::move(on_connected)](
                                               beast::error_code ec, const tcp::endpoint&) mutable {
                                    on_connected(ec);
                                  });
                            });
  }

  beast::tcp_stream& stream() { return stream_; }
  const ForwardTarget& to() const { return to_; }

 private:
  tcp::resolver resolver_;
  beast::tcp_stream stream_;
  ForwardTarget to_;
};

class HttpForward : public std::enable_shared_from_this<HttpForward> {
 public:
  HttpForward(net::any_io_executor executor, const ForwardTarget& to, Request request,
              std::function<void(Response)> done)
      : upstream_(executor, to),
        request_(std::move(request)),
        done_(std::move(done)),
        version_(request_.version()),
        keep_alive_(request_.keep_alive()),
        head_(request_.method() == http::verb::head) {
    parser_.body_limit(kAnswerLimit);
  }

  void run(const std::string& self_node) {
    mark_forwarded(request_, self_node);
    upstream_.connect([self = shared_from_this()](beast::error_code ec) {
      if (ec) return self->fail(ec);
      self->upstream_.stream().expires_after(kWriteTimeout);
      http::async_write(
          self->upstream_.stream(), self->request_, [self](beast::error_code ec, std::size_t) {
            if (ec) return self->fail(ec);
            self->upstream_.stream().expires_after(kAnswerTimeout);
            http::async_read(self->upstream_.stream(), self->buffer_, self->parser_,
                             [self](beast::error_code ec, std::size_t) { self->on_answer(ec); });
          });
    });
  }

 private:
  void on_answer(beast::error_code ec) {
    if (ec) return fail(ec);
    Response answer = parser_.release();
    answer.keep_alive(keep_alive_);
    if (!head_) answer.prepare_payload();
    close_upstream();
    done_(std::move(answer));
  }

  void fail(beast::error_code ec) {
    close_upstream();
    auto answer = json_error(http::status::service_unavailable, unreachable(upstream_.to(), ec),
                             version_, keep_alive_);
    answer.set(http::field::retry_after, "2");
    done_(std::move(answer));
  }

  void close_upstream() {
    beast::error_code ignored;
    upstream_.stream().socket().close(ignored);
  }

  Upstream upstream_;
  Request request_;
  std::function<void(Response)> done_;
  unsigned version_;
  bool keep_alive_;
  bool head_;
  beast::flat_buffer buffer_;
  http::response_parser<http::string_body> parser_;
};

class WebSocketForward : public std::enable_shared_from_this<WebSocketForward> {
 public:
  WebSocketForward(transport::MaybeTlsStream&& client, beast::flat_buffer&& already_read,
                   const ForwardTarget& to, Request&& upgrade)
      : client_(std::move(client)),
        client_bytes_(std::move(already_read)),
        upstream_(client_.get_executor(), to),
        upgrade_(std::move(upgrade)) {
    parser_.body_limit(64 * 1024);  // a refusal's JSON, or nothing (101)
  }

  void run(const std::string& self_node) {
    // The owner's own timeouts (pings, idle) govern the socket from here on.
    client_.tcp().expires_never();
    mark_forwarded(upgrade_, self_node);
    upstream_.connect([self = shared_from_this()](beast::error_code ec) {
      if (ec) return self->refuse(ec);
      self->upstream_.stream().expires_after(kWriteTimeout);
      http::async_write(
          self->upstream_.stream(), self->upgrade_, [self](beast::error_code ec, std::size_t) {
            if (ec) return self->refuse(ec);
            http::async_read(self->upstream_.stream(), self->upstream_bytes_, self->parser_,
                             [self](beast::error_code ec, std::size_t) { self->on_answer(ec); });
          });
    });
  }

 private:
  void refuse(beast::error_code ec) {
    beast::error_code ignored;
    upstream_.stream().socket().close(ignored);
    upgrade_.erase(kForwardedByHeader);
    refuse_websocket(std::move(client_), std::move(upgrade_),
                     beast::websocket::close_code::try_again_later,
                     unreachable(upstream_.to(), ec));
  }

  void on_answer(beast::error_code ec) {
    if (ec) return refuse(ec);
    upstream_.stream().expires_never();
    answer_ = parser_.release();
    // The owner's answer as it is: 101 and its accept key, or its refusal (which closes).
    http::async_write(client_, answer_,
                      [self = shared_from_this()](beast::error_code ec, std::size_t) {
                        if (ec || self->answer_.result() != http::status::switching_protocols)
                          return self->close();
                        self->start_pumps();
                      });
  }

  // Bytes either side sent before the pumps start (the owner's first frames, read along with its
  // 101) go first.
  void start_pumps() {
    // A view is long and mostly one-way: a peer gone without a FIN (a host down, a cable out)
    // shows as failed keepalive probes within about 25 s, and the other side is closed then.
    keep_alive(upstream_.stream().socket());
    keep_alive(client_.tcp().socket());
    auto self = shared_from_this();
    net::async_write(client_, upstream_bytes_.data(), [self](beast::error_code ec, std::size_t n) {
      if (ec) return self->close();
      self->upstream_bytes_.consume(n);
      self->pump_down();
    });
    net::async_write(upstream_.stream(), client_bytes_.data(),
                     [self](beast::error_code ec, std::size_t n) {
                       if (ec) return self->close();
                       self->client_bytes_.consume(n);
                       self->pump_up();
                     });
  }

  // Owner -> browser.
  void pump_down() {
    upstream_.stream().async_read_some(
        net::buffer(down_), [self = shared_from_this()](beast::error_code ec, std::size_t n) {
          if (ec) return self->close();
          net::async_write(self->client_, net::buffer(self->down_.data(), n),
                           [self](beast::error_code ec, std::size_t) {
                             if (ec) return self->close();
                             self->pump_down();
                           });
        });
  }

  // Browser -> owner.
  void pump_up() {
    client_.async_read_some(
        net::buffer(up_), [self = shared_from_this()](beast::error_code ec, std::size_t n) {
          if (ec) return self->close();
          net::async_write(self->upstream_.stream(), net::buffer(self->up_.data(), n),
                           [self](beast::error_code ec, std::size_t) {
                             if (ec) return self->close();
                             self->pump_up();
                           });
        });
  }

  // Either side gone: both go (the other pump's pending operation ends with an error).
  void close() {
    beast::error_code ignored;
    upstream_.stream().socket().close(ignored);
    client_.tcp().socket().close(ignored);
  }

  transport::MaybeTlsStream client_;
  beast::flat_buffer client_bytes_;
  Upstream upstream_;
  Request upgrade_;
  beast::flat_buffer upstream_bytes_;
  http::response_parser<http::string_body> parser_;
  Response answer_;
  std::array<char, 16 * 1024> down_{};
  std::array<char, 16 * 1024> up_{};
};

}  // namespace

void forward_http(net::any_io_executor executor, const ForwardTarget& to,
                  const std::string& self_node, Request request,
                  std::function<void(Response)> done) {
  std::make_shared<HttpForward>(std::move(executor), to, std::move(request), std::move(done))
      ->run(self_node);
}

void forward_websocket(transport::MaybeTlsStream&& client, beast::flat_buffer&& already_read,
                       const ForwardTarget& to, const std::string& self_node, Request&& upgrade) {
  std::make_shared<WebSocketForward>(std::move(client), std::move(already_read), to,
                                     std::move(upgrade))
      ->run(self_node);
}

}  // namespace incise::server
