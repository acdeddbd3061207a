#pragma once
// Polling for what another thread brings about (a replay's engine, a render thread): the tests
// wait for a condition rather than for a fixed time.
#include <chrono>
#include <functional>
#include <thread>

namespace incise::test {

// Polls `done` every millisecond until it holds (true) or `limit` passes (false).
inline bool wait_for(const std::function<bool()>& done,
                     std::chrono::milliseconds limit = std::chrono::seconds(20)) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

}  // namespace incise::test
