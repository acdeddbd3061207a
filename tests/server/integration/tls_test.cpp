// The server over TLS (--tls-cert, --tls-key): the real incise-server with a certificate made by
// the openssl command for this run, a Beast client that verifies it, and the real agent over
// wss://. Plain HTTP to the TLS port is sent to https://.
#include <gtest/gtest.h>
#include <signal.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "server_fixture.h"
#include "transport/maybe_tls_stream.h"
#include "transport/tls_contexts.h"

namespace incise::server::test {
namespace {

namespace net = boost::asio;
namespace beast = boost::beast;
using namespace std::chrono_literals;

constexpr const char* kListeningTls = "incise-server: listening on https://127.0.0.1:";

// A self-signed P-256 certificate for 127.0.0.1 and localhost, from the openssl command (as an
// administrator would make one for a trial); `name` distinguishes the files.
void make_certificate(const std::filesystem::path& dir, const std::string& name) {
  const auto key = dir / (name + "-key.pem");
  const auto cert = dir / (name + ".pem");
  ChildProcess openssl({"/usr/bin/openssl", "req", "-x509", "-newkey", "ec", "-pkeyopt",
                        "ec_paramgen_curve:prime256v1", "-nodes", "-days", "2", "-subj",
                        "/CN=localhost", "-addext", "subjectAltName=IP:127.0.0.1,DNS:localhost",
                        "-keyout", key.string(), "-out", cert.string()});
  const auto status = openssl.wait_for_exit(30s);
  if (status != 0) throw std::runtime_error("openssl req failed: " + openssl.stderr_text());
}

struct Reply {
  int status = 0;
  std::string hsts;
  std::string set_cookie;
  std::string body;
};

// One HTTPS request to 127.0.0.1 that trusts only `ca_file` and checks that the certificate names
// `server_name`. Throws boost::system::system_error when the connection or the handshake fails.
Reply https_request(unsigned short port, const std::string& ca_file, http::verb method,
                    const std::string& target, const std::string& body = {},
                    const std::string& server_name = "127.0.0.1") {
  net::io_context io;
  const auto context = transport::make_client_tls(ca_file);
  transport::MaybeTlsStream stream(beast::tcp_stream(io), *context);
  stream.tcp().connect(net::ip::tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
  if (!stream.expect_server(server_name)) throw std::runtime_error("cannot name the server");
  stream.handshake(net::ssl::stream_base::client);
  http::request<http::string_body> request{method, target, 11};
  request.set(http::field::host, "127.0.0.1:" + std::to_string(port));
  if (!body.empty()) {
    request.set(http::field::content_type, "application/json");
    request.body() = body;
  }
  request.prepare_payload();
  http::write(stream, request);
  beast::flat_buffer buffer;
  http::response<http::string_body> response;
  http::read(stream, buffer, response);
  return {static_cast<int>(response.result_int()),
          std::string(response[http::field::strict_transport_security]),
          std::string(response[http::field::set_cookie]), response.body()};
}

class TlsServer : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    signal(SIGPIPE, SIG_IGN);
    dir_ = std::make_unique<TempDir>("incise-tls-it");
    try {
      make_certificate(dir_->path(), "server");
      make_certificate(dir_->path(), "stranger");
      const auto web = dir_->path() / "web";
      std::filesystem::create_directories(web);
      std::ofstream(web / "index.html") << kIndexHtml;
      server_ = std::make_unique<ChildProcess>(std::vector<std::string>{
          INCISE_SERVER_BIN, "--port", "0", "--host", "127.0.0.1", "--data",
          (dir_->path() / "data").string(), "--demo", "--web", web.string(), "--tls-cert",
          cert().string(), "--tls-key", (dir_->path() / "server-key.pem").string()});
      const auto line = server_->wait_for_line(kListeningTls, 20s);
      if (!line) throw std::runtime_error("not listening: " + server_->stderr_text());
      port_ = static_cast<unsigned short>(
          std::stoi(line->substr(std::string_view(kListeningTls).size())));
    } catch (const std::exception& e) {
      start_error_ = e.what();
    }
  }
  static void TearDownTestSuite() {
    server_.reset();
    dir_.reset();
  }
  void SetUp() override { ASSERT_TRUE(server_ && port_ != 0) << start_error_; }
  void TearDown() override {
    EXPECT_TRUE(server_->running()) << server_->stderr_text();
    EXPECT_EQ(server_->stderr_text().find("internal error"), std::string::npos);
  }

  static std::filesystem::path cert() { return dir_->path() / "server.pem"; }
  static std::filesystem::path stranger() { return dir_->path() / "stranger.pem"; }

  // The real agent, dialling this server over wss:// and trusting `ca`.
  static std::unique_ptr<ChildProcess> start_agent(const std::filesystem::path& ca) {
    return std::make_unique<ChildProcess>(
        std::vector<std::string>{INCISE_AGENT_BIN, "--server",
                                 "wss://127.0.0.1:" + std::to_string(port_) + "/agent", "--ca",
                                 ca.string()},
        incise::test::environment_with("INCISE_STATION_TOKEN", kStationToken));
  }

  // Waits up to `timeout` for `text` in the child's stderr.
  static bool stderr_shows(ChildProcess& child, const std::string& text,
                           std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      if (child.stderr_text().find(text) != std::string::npos) return true;
      std::this_thread::sleep_for(50ms);
    }
    return child.stderr_text().find(text) != std::string::npos;
  }

  static inline std::unique_ptr<TempDir> dir_;
  static inline std::unique_ptr<ChildProcess> server_;
  static inline unsigned short port_ = 0;
  static inline std::string start_error_;
};

TEST_F(TlsServer, ServesTheApiOverTlsWithStrictTransportSecurity) {
  const auto reply = https_request(port_, cert().string(), http::verb::get, "/api/health");
  EXPECT_EQ(reply.status, 200) << reply.body;
  EXPECT_EQ(nlohmann::json::parse(reply.body).value("status", ""), "ok");
  EXPECT_EQ(reply.hsts, "max-age=31536000");
}

TEST_F(TlsServer, TheLoginCookieIsSecureWithoutBeingToldSo) {
  const nlohmann::json credentials = {{"username", kTrainee.username},
                                      {"password", kTrainee.password}};
  const auto reply =
      https_request(port_, cert().string(), http::verb::post, "/api/login", credentials.dump());
  ASSERT_EQ(reply.status, 200) << reply.body;
  EXPECT_NE(reply.set_cookie.find("; Secure"), std::string::npos) << reply.set_cookie;
  EXPECT_NE(reply.set_cookie.find("HttpOnly"), std::string::npos) << reply.set_cookie;
}

TEST_F(TlsServer, AClientThatTrustsAnotherCertificateIsNotServed) {
  try {
    https_request(port_, stranger().string(), http::verb::get, "/api/health");
    FAIL() << "the handshake succeeded against an untrusted certificate";
  } catch (const boost::system::system_error& e) {
    EXPECT_EQ(e.code().category(), net::error::get_ssl_category()) << e.code().message();
  }
  EXPECT_EQ(https_request(port_, cert().string(), http::verb::get, "/api/health").status, 200);
}

// What a plain-HTTP client gets from the HTTPS port, and what it leaves behind: nothing.
std::string plain_exchange(unsigned short port, const std::string& request) {
  net::io_context io;
  net::ip::tcp::socket socket(io);
  socket.connect(net::ip::tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
  net::write(socket, net::buffer(request));
  std::string received;
  boost::system::error_code ec;
  for (;;) {
    char chunk[4096];
    const auto n = socket.read_some(net::buffer(chunk), ec);
    received.append(chunk, n);
    if (ec) break;  // the server closes after answering
  }
  return received;
}

TEST_F(TlsServer, ATrustedCertificateForAnotherNameIsRefused) {
  // The server's own certificate is trusted here; it names 127.0.0.1 and localhost only.
  EXPECT_EQ(
      https_request(port_, cert().string(), http::verb::get, "/api/health", {}, "localhost").status,
      200);
  try {
    https_request(port_, cert().string(), http::verb::get, "/api/health", {}, "incise.example");
    FAIL() << "the handshake accepted a certificate for another name";
  } catch (const boost::system::system_error& e) {
    EXPECT_EQ(e.code().category(), net::error::get_ssl_category()) << e.code().message();
  }
  // And a client that names no server at all does not even try.
  net::io_context io;
  const auto context = transport::make_client_tls(cert().string());
  transport::MaybeTlsStream stream(beast::tcp_stream(io), *context);
  stream.tcp().connect(net::ip::tcp::endpoint(net::ip::make_address("127.0.0.1"), port_));
  EXPECT_THROW(stream.handshake(net::ssl::stream_base::client), boost::system::system_error);
}

TEST_F(TlsServer, ABrowserSentToHttpIsRedirectedToHttps) {
  const std::string port = std::to_string(port_);
  const auto answer =
      plain_exchange(port_, "GET /trainee?week=2 HTTP/1.1\r\nHost: 127.0.0.1:" + port + "\r\n\r\n");
  EXPECT_TRUE(answer.starts_with("HTTP/1.1 301")) << answer;
  EXPECT_NE(answer.find("Location: https://127.0.0.1:" + port + "/trainee?week=2\r\n"),
            std::string::npos)
      << answer;
  // Never HSTS over plain HTTP, where anyone on the path could have written it.
  EXPECT_EQ(answer.find("Strict-Transport-Security"), std::string::npos) << answer;
  // A login sent in the clear is not followed anywhere: 400, nothing set.
  const std::string body = R"({"username":"trainee","password":"incise-trainee-demo"})";
  const auto login =
      plain_exchange(port_, "POST /api/login HTTP/1.1\r\nHost: 127.0.0.1:" + port +
                                "\r\nContent-Type: application/json\r\nContent-Length: " +
                                std::to_string(body.size()) + "\r\n\r\n" + body);
  EXPECT_TRUE(login.starts_with("HTTP/1.1 400")) << login;
  EXPECT_EQ(login.find("Set-Cookie"), std::string::npos) << login;
  // A target that is not a path is not made into a Location on another host.
  const auto odd = plain_exchange(
      port_, "GET @elsewhere.example/ HTTP/1.1\r\nHost: 127.0.0.1:" + port + "\r\n\r\n");
  EXPECT_EQ(odd.find("Location"), std::string::npos) << odd;
  EXPECT_EQ(https_request(port_, cert().string(), http::verb::get, "/api/health").status, 200);
}

TEST_F(TlsServer, TheAgentLinksOverWssWhenItTrustsTheCertificate) {
  auto agent = start_agent(cert());
  EXPECT_TRUE(stderr_shows(
      *agent, "connected to wss://127.0.0.1:" + std::to_string(port_) + "/agent as station", 20s))
      << agent->stderr_text();
}

TEST_F(TlsServer, TheAgentRefusesAServerItsCaDoesNotVouchFor) {
  auto agent = start_agent(stranger());
  EXPECT_TRUE(stderr_shows(*agent, "TLS handshake: certificate verify failed", 20s))
      << agent->stderr_text();
  EXPECT_EQ(agent->stderr_text().find("as station"), std::string::npos);
}

TEST_F(TlsServer, AnUnusableCertificateOrKeyStopsTheStartWithTheReason) {
  const auto start = [&](const std::filesystem::path& certificate,
                         const std::filesystem::path& key) {
    ChildProcess server({INCISE_SERVER_BIN, "--port", "0", "--data",
                         (dir_->path() / "other-data").string(), "--tls-cert", certificate.string(),
                         "--tls-key", key.string()});
    const auto status = server.wait_for_exit(20s);
    return std::make_pair(status.value_or(-1), server.stderr_text());
  };
  const auto [missing_status, missing] = start(dir_->path() / "none.pem", dir_->path() / "x.pem");
  EXPECT_EQ(missing_status, 1);
  EXPECT_NE(missing.find("cannot use the TLS certificate"), std::string::npos) << missing;
  // The stranger's key does not belong to the server's certificate.
  const auto [mismatch_status, mismatch] = start(cert(), dir_->path() / "stranger-key.pem");
  EXPECT_EQ(mismatch_status, 1);
  EXPECT_NE(mismatch.find("cannot use the TLS private key"), std::string::npos) << mismatch;
}

}  // namespace
}  // namespace incise::server::test
