#pragma once
// Reconnect delays: 0.25 s, doubling per failed attempt, capped at 5 s, so a server restart is
// picked up quickly while an absent server costs one attempt every few seconds.

#include <algorithm>
#include <chrono>

namespace incise::devices::agent {

class Backoff {
 public:
  using Duration = std::chrono::milliseconds;

  explicit Backoff(Duration first = Duration(250), Duration max = Duration(5000))
      : first_(first), max_(max), next_(first) {}

  // The delay before the next attempt; the one after it doubles, up to max.
  Duration next() {
    const Duration delay = next_;
    next_ = std::min(next_ * 2, max_);
    return delay;
  }

  // After a successful connection the next failure starts again from the first delay.
  void reset() { next_ = first_; }

 private:
  Duration first_;
  Duration max_;
  Duration next_;
};

}  // namespace incise::devices::agent
