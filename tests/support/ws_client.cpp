#include "ws_client.h"

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core/buffers_to_string.hpp>
#include <chrono>

namespace incise::server::test {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;

namespace {
constexpr auto kTimeout = std::chrono::seconds(10);
}  // namespace

WsClient::WsClient(const std::string& host, unsigned short port, const std::string& target,
                   const std::vector<std::pair<std::string, std::string>>& headers)
    : ws_(io_) {
  beast::error_code result;
  bool done = false;
  beast::get_lowest_layer(ws_).expires_after(kTimeout);
  beast::get_lowest_layer(ws_).async_connect(
      net::ip::tcp::endpoint(net::ip::make_address(host), port), [&](beast::error_code ec) {
        result = ec;
        done = true;
      });
  run_until(done);
  if (result) throw beast::system_error(result, "connect");
  beast::get_lowest_layer(ws_).expires_never();
  ws_.set_option(websocket::stream_base::timeout{kTimeout, kTimeout, false});
  ws_.set_option(websocket::stream_base::decorator([headers](websocket::request_type& request) {
    for (const auto& [name, value] : headers)
      request.set(name, value);
  }));
  done = false;
  ws_.async_handshake(host + ":" + std::to_string(port), target, [&](beast::error_code ec) {
    result = ec;
    done = true;
  });
  run_until(done);
  if (result) throw beast::system_error(result, "WebSocket handshake");
}

WsClient::~WsClient() {
  beast::error_code ignored;
  beast::get_lowest_layer(ws_).socket().close(ignored);
}

void WsClient::send_text(const std::string& text) {
  beast::error_code result;
  ws_.text(true);
  bool done = false;
  ws_.async_write(net::buffer(text), [&](beast::error_code ec, std::size_t) {
    result = ec;
    done = true;
  });
  run_until(done);
  if (result) throw beast::system_error(result, "write text");
}

void WsClient::send_binary(const std::vector<std::uint8_t>& bytes) {
  beast::error_code result;
  ws_.binary(true);
  bool done = false;
  ws_.async_write(net::buffer(bytes), [&](beast::error_code ec, std::size_t) {
    result = ec;
    done = true;
  });
  run_until(done);
  if (result) throw beast::system_error(result, "write binary");
}

WsEvent WsClient::read() {
  beast::error_code result;
  buffer_.clear();
  bool done = false;
  ws_.async_read(buffer_, [&](beast::error_code ec, std::size_t) {
    result = ec;
    done = true;
  });
  run_until(done);
  WsEvent event;
  if (!result) {
    event.message = beast::buffers_to_string(buffer_.data());
    event.text = ws_.got_text();
    return event;
  }
  event.closed = true;
  event.error = result.message();
  if (result == websocket::error::closed) {
    event.close_code = ws_.reason().code;
    event.close_reason.assign(ws_.reason().reason.data(), ws_.reason().reason.size());
  }
  return event;
}

void WsClient::close() {
  if (!ws_.is_open()) return;
  bool done = false;
  ws_.async_close(websocket::close_code::normal, [&](beast::error_code) { done = true; });
  run_until(done);
}

// Not io_.run(): the stream's idle timer stays pending after an operation completes.
void WsClient::run_until(const bool& done) {
  io_.restart();
  while (!done && io_.run_one() > 0) {
  }
}

}  // namespace incise::server::test
