#pragma once
// The one error type of the REST handlers: an HTTP status and a precise message for the person.
// The router turns it (and the storage layer's typed errors) into `{"error": message}`.
#include <boost/beast/http/status.hpp>
#include <stdexcept>
#include <string>

namespace incise::server {

class ApiError : public std::runtime_error {
 public:
  ApiError(boost::beast::http::status status, const std::string& message)
      : std::runtime_error(message), status_(status) {}
  boost::beast::http::status status() const { return status_; }

 private:
  boost::beast::http::status status_;
};

}  // namespace incise::server
