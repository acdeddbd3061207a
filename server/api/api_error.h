#pragma once
// The one error type of the REST handlers: an HTTP status and a precise message for the person.
// The router turns it (and the storage layer's typed errors) into `{"error": message}`.
#include <boost/beast/http/status.hpp>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace incise::server {

class ApiError : public std::runtime_error {
 public:
  using Headers = std::vector<std::pair<std::string, std::string>>;

  ApiError(boost::beast::http::status status, const std::string& message, Headers headers = {})
      : std::runtime_error(message), status_(status), headers_(std::move(headers)) {}
  boost::beast::http::status status() const { return status_; }
  // Sent with the error, such as Retry-After with a 429.
  const Headers& headers() const { return headers_; }

 private:
  boost::beast::http::status status_;
  Headers headers_;
};

}  // namespace incise::server
