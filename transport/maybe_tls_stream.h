#pragma once
// A TCP stream that speaks TLS or plain text, chosen per connection at run time: the server serves
// HTTPS when it is given a certificate (--tls-cert, --tls-key) and plain HTTP otherwise, and the
// agent dials wss:// or ws://. One concrete type, so that the HTTP session, the WebSocket sessions
// and the agent's link are written once rather than as templates over two streams. Both the
// server and the agent use it; beside the stream it keeps only whether a client named its server.
//
// It is an Asio AsyncReadStream and AsyncWriteStream (what Beast's http::async_read and
// websocket::stream need), and it tells a websocket::stream how to tear it down (the free
// teardown functions below, found by argument-dependent lookup).
#include <boost/asio/ip/address.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/asio/ssl/host_name_verification.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket/ssl.hpp>
#include <boost/beast/websocket/teardown.hpp>
#include <string>
#include <utility>
#include <variant>

namespace incise::transport {

class MaybeTlsStream {
 public:
  using Tcp = boost::beast::tcp_stream;
  using Tls = boost::beast::ssl_stream<boost::beast::tcp_stream>;
  using executor_type = Tcp::executor_type;

  // Plain text over an accepted socket or a stream that is still to connect.
  explicit MaybeTlsStream(Tcp&& tcp) : stream_(std::in_place_type<Tcp>, std::move(tcp)) {}
  // TLS with `context` (which must outlive the stream) over the same; the handshake is still to
  // be done (handshake_server / handshake_client).
  MaybeTlsStream(Tcp&& tcp, boost::asio::ssl::context& context)
      : stream_(std::in_place_type<Tls>, std::move(tcp), context) {}

  MaybeTlsStream(MaybeTlsStream&&) = default;

  // A TLS server whose client turned out to speak plain text (beast::async_detect_ssl): from here
  // on the stream is the plain TCP stream underneath. Nothing on a plain stream.
  void become_plain() {
    if (!is_tls()) return;
    Tcp tcp(std::move(this->tcp()));
    stream_.emplace<Tcp>(std::move(tcp));
  }

  executor_type get_executor() noexcept { return tcp().get_executor(); }
  bool is_tls() const noexcept { return std::holds_alternative<Tls>(stream_); }
  // The TCP stream underneath (connect, timeouts, the peer's address).
  Tcp& tcp() noexcept {
    return std::visit([](auto& s) -> Tcp& { return boost::beast::get_lowest_layer(s); }, stream_);
  }
  Tls* tls() noexcept { return std::get_if<Tls>(&stream_); }

  template <class MutableBuffers, class Token>
  auto async_read_some(const MutableBuffers& buffers, Token&& token) {
    return boost::asio::async_initiate<Token, void(boost::system::error_code, std::size_t)>(
        [this](auto handler, const MutableBuffers& b) {
          std::visit([&](auto& s) { s.async_read_some(b, std::move(handler)); }, stream_);
        },
        token, buffers);
  }

  template <class ConstBuffers, class Token>
  auto async_write_some(const ConstBuffers& buffers, Token&& token) {
    return boost::asio::async_initiate<Token, void(boost::system::error_code, std::size_t)>(
        [this](auto handler, const ConstBuffers& b) {
          std::visit([&](auto& s) { s.async_write_some(b, std::move(handler)); }, stream_);
        },
        token, buffers);
  }

  // Blocking reads and writes (the agent's self-test).
  template <class MutableBuffers>
  std::size_t read_some(const MutableBuffers& buffers) {
    return std::visit([&](auto& s) { return s.read_some(buffers); }, stream_);
  }
  template <class MutableBuffers>
  std::size_t read_some(const MutableBuffers& buffers, boost::system::error_code& ec) {
    return std::visit([&](auto& s) { return s.read_some(buffers, ec); }, stream_);
  }
  template <class ConstBuffers>
  std::size_t write_some(const ConstBuffers& buffers) {
    return std::visit([&](auto& s) { return s.write_some(buffers); }, stream_);
  }
  template <class ConstBuffers>
  std::size_t write_some(const ConstBuffers& buffers, boost::system::error_code& ec) {
    return std::visit([&](auto& s) { return s.write_some(buffers, ec); }, stream_);
  }

  // A client, before its handshake: names the server it dials (SNI, for a host name) and accepts
  // only a certificate for `host` (a name or an IP address) that the context's CAs vouch for.
  // Nothing on a plain stream. False if OpenSSL refused the name. A TLS client's handshake fails
  // (invalid_argument) until this was called: a chain check alone would accept any certificate
  // the CAs issued, for any name.
  bool expect_server(const std::string& host) {
    auto* s = tls();
    if (!s) return true;
    server_named_ = true;
    s->set_verify_callback(boost::asio::ssl::host_name_verification(host));
    boost::system::error_code not_an_address;
    boost::asio::ip::make_address(host, not_an_address);
    if (!not_an_address) return true;  // RFC 6066: no SNI for an IP literal
    return SSL_set_tlsext_host_name(s->native_handle(), host.c_str()) == 1;
  }

  // The TLS handshake, or nothing on a plain stream (blocking). Throws system_error.
  void handshake(boost::asio::ssl::stream_base::handshake_type type) {
    if (unnamed_client(type)) {
      throw boost::system::system_error(boost::asio::error::invalid_argument, "server not named");
    }
    if (auto* s = tls()) s->handshake(type);
  }

  // A TLS server's handshake whose first bytes were already read (into `buffers`, e.g. by
  // beast::async_detect_ssl); the handler gets (error, bytes of `buffers` used). TLS only.
  template <class ConstBuffers, class Handler>
  void async_handshake(boost::asio::ssl::stream_base::handshake_type type,
                       const ConstBuffers& buffers, Handler&& handler) {
    tls()->async_handshake(type, buffers, std::forward<Handler>(handler));
  }

  // The TLS handshake, or an immediate success on a plain stream.
  template <class Handler>
  void async_handshake(boost::asio::ssl::stream_base::handshake_type type, Handler&& handler) {
    auto* s = tls();
    if (s && !unnamed_client(type)) return s->async_handshake(type, std::forward<Handler>(handler));
    const boost::system::error_code result =
        s ? boost::asio::error::invalid_argument : boost::system::error_code{};
    boost::asio::post(get_executor(),
                      boost::beast::bind_front_handler(std::forward<Handler>(handler), result));
  }

  // How Beast's timeouts close a stream (websocket::stream's idle and handshake timeouts): the
  // socket underneath, abruptly.
  friend void beast_close_socket(MaybeTlsStream& stream) { stream.tcp().close(); }

  template <class Handler>
  friend void async_teardown(boost::beast::role_type role, MaybeTlsStream& stream,
                             Handler&& handler) {
    std::visit(
        [&](auto& s) {
          using boost::beast::websocket::async_teardown;
          async_teardown(role, s, std::forward<Handler>(handler));
        },
        stream.stream_);
  }

  friend void teardown(boost::beast::role_type role, MaybeTlsStream& stream,
                       boost::system::error_code& ec) {
    std::visit(
        [&](auto& s) {
          using boost::beast::websocket::teardown;
          teardown(role, s, ec);
        },
        stream.stream_);
  }

 private:
  bool unnamed_client(boost::asio::ssl::stream_base::handshake_type type) const {
    return type == boost::asio::ssl::stream_base::client && is_tls() && !server_named_;
  }

  std::variant<Tcp, Tls> stream_;
  bool server_named_ = false;  // expect_server was called
};

// A stream over `tcp`: TLS with `context`, or plain text when it is null.
inline MaybeTlsStream make_stream(boost::beast::tcp_stream&& tcp,
                                  boost::asio::ssl::context* context) {
  if (context) return MaybeTlsStream(std::move(tcp), *context);
  return MaybeTlsStream(std::move(tcp));
}

// Whether `ec` is how a TLS peer ends a connection without a close_notify (browsers often do):
// the same as a plain end of stream to the caller.
inline bool is_truncation(const boost::system::error_code& ec) {
  return ec == boost::asio::ssl::error::stream_truncated;
}

}  // namespace incise::transport
