#pragma once
// A small synchronous HTTP/1.1 client for the integration tests (Boost.Beast), with a cookie jar
// for the session cookie. One keep-alive connection, reopened when the server closed it; every
// operation has a timeout, so that a hung server fails a test instead of hanging it.
#include <boost/asio/io_context.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/http.hpp>
#include <chrono>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace incise::server::test {

namespace http = boost::beast::http;

struct HttpResponse {
  int status = 0;  // 0: no response; `transport_error` says why
  std::string body;
  std::string content_type;
  std::vector<std::string> set_cookies;  // every Set-Cookie header, in order
  std::string retry_after;               // the Retry-After header, if any
  bool keep_alive = false;
  std::string transport_error;

  // The body as JSON; discarded (is_discarded()) when it is not JSON.
  nlohmann::json json() const;
  // The "error" member of a JSON error body, or a description of what the body is instead.
  std::string error() const;
};

class HttpClient {
 public:
  using Headers = std::vector<std::pair<std::string, std::string>>;

  HttpClient(std::string host, unsigned short port);

  HttpResponse get(std::string_view target);
  // Sends `body` as JSON with Content-Type application/json.
  HttpResponse post(std::string_view target, const nlohmann::json& body);
  HttpResponse put(std::string_view target, const nlohmann::json& body);
  HttpResponse del(std::string_view target);
  // Anything else: `headers` are added to Host, Cookie and Content-Length.
  HttpResponse request(http::verb method, std::string_view target, std::string body = {},
                       const Headers& headers = {});

  // Logs in and keeps the session cookie; returns the response.
  HttpResponse login(const std::string& username, const std::string& password);

  // Opens the connection now (so that a later request starts without connecting).
  void connect();
  void disconnect();

  std::optional<std::string> cookie(const std::string& name) const;
  void set_cookie(const std::string& name, const std::string& value) { jar_[name] = value; }
  std::string origin() const;  // "http://host:port", this server's own origin

 private:
  HttpResponse exchange(const http::request<http::string_body>& request);
  void remember_cookies(const HttpResponse& response);
  void run_until(const bool& done);

  std::string host_;
  unsigned short port_;
  boost::asio::io_context io_;
  std::optional<boost::beast::tcp_stream> stream_;
  boost::beast::flat_buffer buffer_;
  std::map<std::string, std::string> jar_;
};

inline constexpr auto kHttpTimeout = std::chrono::seconds(10);

}  // namespace incise::server::test
