#include "devices/agent/self_test.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <ostream>
#include <string>
#include <thread>

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

#include "devices/protocol.h"
#include "transport/maybe_tls_stream.h"

#ifndef INCISE_AGENT_VERSION
#define INCISE_AGENT_VERSION "dev"
#endif

namespace incise::devices::agent {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using Clock = std::chrono::steady_clock;

std::string format(const char* format, auto... values) {
  char text[256];
  std::snprintf(text, sizeof text, format, values...);
  return text;
}

bool report(std::ostream& out, bool ok, const std::string& what) {
  out << (ok ? "ok   " : "FAIL ") << what << "\n";
  return ok;
}

bool check_device(std::size_t index, Device& device, std::ostream& out) {
  const std::string what = "device " + std::to_string(index) + " " + std::string(device.name());
  const Clock::time_point start = Clock::now();
  DeviceState first;
  double travel = 0;
  DeviceState previous;
  for (int i = 0; i < 200; ++i) {
    std::this_thread::sleep_until(start + std::chrono::milliseconds(i));
    const DeviceState s = device.poll(std::chrono::duration<double>(Clock::now() - start).count());
    device.set_force({});
    const Vec3& p = s.position;
    const Quat& q = s.orientation;
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      return report(out, false, what + format(": poll %d gave a non-finite position", i));
    }
    const double norm = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    if (!(std::abs(norm - 1.0) <= kUnitQuaternionTolerance)) {
      return report(out, false,
                    what + format(": poll %d gave |q| = %g, not a unit quaternion", i, norm));
    }
    if (!device.fault().empty()) {
      return report(out, false, what + ": " + std::string(device.fault()));
    }
    if (i == 0) first = s;
    if (i > 0) {
      travel += std::hypot(p.x - previous.position.x, p.y - previous.position.y,
                           p.z - previous.position.z);
    }
    previous = s;
  }
  const DeviceCapabilities caps = device.capabilities();
  return report(
      out, true,
      what + format(": 200 polls, states valid, tip at (%.4f, %.4f, %.4f) m, moved %.1f mm; %s",
                    previous.position.x, previous.position.y, previous.position.z, travel * 1e3,
                    caps.has_force_output ? "force output" : "no force output"));
}

bool check_timer(std::ostream& out) {
  std::vector<double> jitter_us;
  Clock::time_point deadline = Clock::now();
  Clock::time_point previous = deadline;
  for (int i = 0; i < 200; ++i) {
    deadline += std::chrono::milliseconds(1);
    std::this_thread::sleep_until(deadline);
    const Clock::time_point now = Clock::now();
    if (i > 0) {
      jitter_us.push_back(
          std::abs(std::chrono::duration<double, std::micro>(now - previous).count() - 1000.0));
    }
    previous = now;
  }
  std::sort(jitter_us.begin(), jitter_us.end());
  const double p99 = jitter_us[jitter_us.size() * 99 / 100];
  return report(
      out, p99 <= 1000.0,
      format("loop timer: 200 ticks at 1 kHz, period jitter p99 %.0f us (limit 1000 us)", p99));
}

bool check_link(const AgentOptions& options, asio::ssl::context* tls, std::ostream& out) {
  const std::string what = "link " + options.server.url();
  try {
    asio::io_context io;
    asio::ip::tcp::resolver resolver(io);
    websocket::stream<transport::MaybeTlsStream> ws(
        transport::make_stream(beast::tcp_stream(io), tls));
    ws.next_layer().tcp().expires_after(std::chrono::seconds(5));
    const auto endpoints = resolver.resolve(options.server.host, options.server.port);
    ws.next_layer().tcp().connect(endpoints);
    if (!ws.next_layer().expect_server(options.server.host)) {
      return report(out, false, what + ": TLS: cannot name the server");
    }
    ws.next_layer().handshake(asio::ssl::stream_base::client);
    ws.handshake(options.server.host + ":" + options.server.port, options.server.target);
    ws.text(true);
    ws.write(asio::buffer(
        build_hello({options.token, "incise-agent/" INCISE_AGENT_VERSION " (self-test)"})));
    beast::flat_buffer buffer;
    bool got_welcome = false;
    beast::error_code read_error;
    ws.async_read(buffer, [&](beast::error_code ec, std::size_t) {
      read_error = ec;
      got_welcome = !ec;
    });
    io.run_for(std::chrono::seconds(5));
    if (read_error == websocket::error::closed) {
      return report(out, false,
                    what + ": refused (" + std::string(ws.reason().reason.c_str()) + ")");
    }
    if (read_error) return report(out, false, what + ": read welcome: " + read_error.message());
    if (!got_welcome) return report(out, false, what + ": no welcome within 5 s");
    io.restart();
    const auto welcome = parse_welcome(beast::buffers_to_string(buffer.data()));
    if (!welcome) return report(out, false, what + ": " + welcome.error);
    report(out, true,
           what + ": welcomed as station " + std::to_string(welcome.value->station_id) + " \"" +
               welcome.value->station_name + "\"");
    // Pings are answered by the server's WebSocket layer itself: the round trip of the network
    // and the server's io thread, without a session.
    std::vector<double> round_trips_ms;
    Clock::time_point sent;
    ws.control_callback([&](websocket::frame_type kind, beast::string_view) {
      if (kind == websocket::frame_type::pong) {
        round_trips_ms.push_back(
            std::chrono::duration<double, std::milli>(Clock::now() - sent).count());
      }
    });
    // A read stays pending throughout (pongs arrive during reads; a session notice may too).
    bool reading = true;
    std::function<void()> read_next = [&] {
      ws.async_read(buffer, [&](beast::error_code ec, std::size_t) {
        if (ec) {
          reading = false;
          return;
        }
        buffer.consume(buffer.size());
        read_next();
      });
    };
    read_next();
    std::string failure;
    for (int i = 0; i < 20 && failure.empty(); ++i) {
      const std::size_t before = round_trips_ms.size();
      sent = Clock::now();
      ws.async_ping({}, [](beast::error_code) {});
      const Clock::time_point deadline = sent + std::chrono::milliseconds(500);
      while (round_trips_ms.size() == before && reading && Clock::now() < deadline)
        io.run_one_until(deadline);
      if (round_trips_ms.size() == before)
        failure = format(": ping %d got no pong within 500 ms", i);
    }
    ws.next_layer().tcp().expires_after(std::chrono::seconds(1));
    ws.async_close(websocket::close_code::normal, [](beast::error_code) {});
    io.run_for(std::chrono::seconds(1));
    if (!failure.empty()) return report(out, false, what + failure);
    std::sort(round_trips_ms.begin(), round_trips_ms.end());
    const double median = round_trips_ms[round_trips_ms.size() / 2];
    const bool ok = median <= 50.0;
    return report(out, ok,
                  what + format(": 20 pings, round trip median %.2f ms, max %.2f ms%s", median,
                                round_trips_ms.back(), ok ? "" : " (limit 50 ms)"));
  } catch (const beast::system_error& e) {
    return report(out, false, what + ": " + e.code().message());
  }
}

}  // namespace

bool run_self_test(const AgentOptions& options, const std::vector<Device*>& devices,
                   asio::ssl::context* tls, std::ostream& out) {
  bool ok = true;
  for (std::size_t i = 0; i < devices.size(); ++i)
    ok = check_device(i, *devices[i], out) && ok;
  ok = check_timer(out) && ok;
  ok = check_link(options, tls, out) && ok;
  out << (ok ? "self-test passed" : "self-test FAILED") << "\n";
  return ok;
}

}  // namespace incise::devices::agent
