#include "server/login_limiter.h"

namespace incise::server {

void LoginLimiter::forget_old(std::deque<std::int64_t>& failures, std::int64_t now) const {
  while (!failures.empty() && failures.front() <= now - window_s_)
    failures.pop_front();
}

std::int64_t LoginLimiter::retry_after(const std::string& address, std::int64_t now) {
  std::lock_guard lock(mutex_);
  auto it = failures_.find(address);
  if (it == failures_.end()) return 0;
  forget_old(it->second, now);
  if (static_cast<int>(it->second.size()) < max_failures_) return 0;
  return it->second.front() + window_s_ - now;
}

void LoginLimiter::record_failure(const std::string& address, std::int64_t now) {
  std::lock_guard lock(mutex_);
  auto& failures = failures_[address];
  forget_old(failures, now);
  failures.push_back(now);
  // Bound memory under a flood of distinct addresses.
  if (failures_.size() > 10000) failures_.erase(failures_.begin());
}

void LoginLimiter::record_success(const std::string& address) {
  std::lock_guard lock(mutex_);
  failures_.erase(address);
}

}  // namespace incise::server
