#include "http_client.h"

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core/error.hpp>

namespace incise::server::test {

namespace net = boost::asio;
namespace beast = boost::beast;

nlohmann::json HttpResponse::json() const {
  return nlohmann::json::parse(body, nullptr, false);
}

std::string HttpResponse::error() const {
  const auto j = json();
  if (j.is_object() && j.contains("error") && j["error"].is_string()) {
    return j["error"].get<std::string>();
  }
  return "(no JSON error; status " + std::to_string(status) + ", body '" + body + "'" +
         (transport_error.empty() ? "" : ", " + transport_error) + ")";
}

HttpClient::HttpClient(std::string host, unsigned short port)
    : host_(std::move(host)), port_(port) {}

std::string HttpClient::origin() const {
  return "http://" + host_ + ":" + std::to_string(port_);
}

void HttpClient::connect() {
  if (stream_) return;
  stream_.emplace(io_);
  stream_->expires_after(kHttpTimeout);
  beast::error_code result;
  bool done = false;
  stream_->async_connect(net::ip::tcp::endpoint(net::ip::make_address(host_), port_),
                         [&](beast::error_code ec) {
                           result = ec;
                           done = true;
                         });
  run_until(done);
  if (result) {
    stream_.reset();
    throw beast::system_error(result, "connect to " + origin());
  }
}

void HttpClient::disconnect() {
  if (!stream_) return;
  beast::error_code ignored;
  stream_->socket().shutdown(net::ip::tcp::socket::shutdown_both, ignored);
  stream_->socket().close(ignored);
  stream_.reset();
  buffer_.clear();
}

HttpResponse HttpClient::get(std::string_view target) {
  return request(http::verb::get, target);
}

HttpResponse HttpClient::post(std::string_view target, const nlohmann::json& body) {
  return request(http::verb::post, target, body.dump(), {{"Content-Type", "application/json"}});
}

HttpResponse HttpClient::put(std::string_view target, const nlohmann::json& body) {
  return request(http::verb::put, target, body.dump(), {{"Content-Type", "application/json"}});
}

HttpResponse HttpClient::del(std::string_view target) {
  return request(http::verb::delete_, target);
}

HttpResponse HttpClient::login(const std::string& username, const std::string& password) {
  return post("/api/login", {{"username", username}, {"password", password}});
}

HttpResponse HttpClient::request(http::verb method, std::string_view target, std::string body,
                                 const Headers& headers) {
  http::request<http::string_body> req{method, target, 11};
  req.set(http::field::host, host_ + ":" + std::to_string(port_));
  req.set(http::field::user_agent, "incise-server-tests");
  std::string cookies;
  for (const auto& [name, value] : jar_)
    cookies += (cookies.empty() ? "" : "; ") + name + "=" + value;
  if (!cookies.empty()) req.set(http::field::cookie, cookies);
  for (const auto& [name, value] : headers)
    req.set(name, value);
  req.body() = std::move(body);
  req.prepare_payload();
  auto response = exchange(req);
  remember_cookies(response);
  return response;
}

HttpResponse HttpClient::exchange(const http::request<http::string_body>& request) {
  // A kept-alive connection may have been closed by the server meanwhile; then the request is
  // sent again once on a new connection (only when nothing at all came back).
  for (int attempt = 0; attempt < 2; ++attempt) {
    const bool reused = stream_.has_value();
    HttpResponse out;
    try {
      connect();
    } catch (const beast::system_error& e) {
      out.transport_error = e.what();
      return out;
    }
    beast::error_code write_error;
    beast::error_code read_error;
    bool done = false;
    http::response_parser<http::string_body> parser;
    parser.body_limit(64 * 1024 * 1024);
    stream_->expires_after(kHttpTimeout);
    http::async_write(*stream_, request, [&](beast::error_code ec, std::size_t) {
      write_error = ec;
      // Read even after a failed write: the server may have answered (413) and closed early.
      stream_->expires_after(kHttpTimeout);
      http::async_read(*stream_, buffer_, parser, [&](beast::error_code ec2, std::size_t) {
        read_error = ec2;
        done = true;
      });
    });
    run_until(done);
    if (!read_error) {
      const auto& res = parser.get();
      out.status = res.result_int();
      out.body = res.body();
      out.content_type = std::string(res[http::field::content_type]);
      out.retry_after = std::string(res[http::field::retry_after]);
      const auto [first, last] = res.equal_range(http::field::set_cookie);
      for (auto it = first; it != last; ++it)
        out.set_cookies.emplace_back(it->value());
      out.keep_alive = res.keep_alive();
      if (!out.keep_alive) disconnect();
      return out;
    }
    disconnect();
    const bool nothing_came_back = read_error == http::error::end_of_stream ||
                                   read_error == net::error::connection_reset ||
                                   read_error == net::error::broken_pipe;
    if (reused && nothing_came_back && attempt == 0) continue;
    out.transport_error = "write: " + write_error.message() + "; read: " + read_error.message();
    return out;
  }
  return {};
}

void HttpClient::remember_cookies(const HttpResponse& response) {
  for (const auto& header : response.set_cookies) {
    const auto eq = header.find('=');
    if (eq == std::string::npos) continue;
    const auto end = header.find(';');
    const std::string name = header.substr(0, eq);
    const std::string value = header.substr(eq + 1, end == std::string::npos ? end : end - eq - 1);
    if (header.find("Max-Age=0") != std::string::npos || value.empty()) {
      jar_.erase(name);
    } else {
      jar_[name] = value;
    }
  }
}

void HttpClient::run_until(const bool& done) {
  io_.restart();
  while (!done && io_.run_one() > 0) {
  }
}

std::optional<std::string> HttpClient::cookie(const std::string& name) const {
  const auto it = jar_.find(name);
  if (it == jar_.end()) return std::nullopt;
  return it->second;
}

}  // namespace incise::server::test
