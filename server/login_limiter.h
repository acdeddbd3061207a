#pragma once
// Limits failed logins per client address: after `max_failures` failures within `window_s`, further
// attempts are refused until the oldest failure leaves the window. Thread-safe.
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <string>

namespace incise::server {

class LoginLimiter {
 public:
  LoginLimiter(int max_failures = 10, std::int64_t window_s = 300)
      : max_failures_(max_failures), window_s_(window_s) {}

  // Seconds until the address may try again; 0 when it may try now.
  std::int64_t retry_after(const std::string& address, std::int64_t now);
  void record_failure(const std::string& address, std::int64_t now);
  void record_success(const std::string& address);

 private:
  void forget_old(std::deque<std::int64_t>& failures, std::int64_t now) const;

  int max_failures_;
  std::int64_t window_s_;
  std::mutex mutex_;
  std::map<std::string, std::deque<std::int64_t>> failures_;
};

}  // namespace incise::server
