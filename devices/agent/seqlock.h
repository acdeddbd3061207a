#pragma once
// One value published by a single writer to readers that must never block (Lamport's
// readers/writer scheme as in the Linux seqlock): the io thread publishes each received force
// model, the haptic thread reads the latest at every tick. The writer never waits; a reader
// retries only if it raced with a write, which takes a few nanoseconds.
//
// Allocation-free and lock-free; the value is kept as atomic words (see atomic_words.h).

#include <atomic>
#include <cstdint>

#include "devices/agent/atomic_words.h"

namespace incise::devices::agent {

template <typename T>
class Seqlock {
 public:
  // Writer only.
  void publish(const T& value) {
    const uint64_t sequence = sequence_.load(std::memory_order_relaxed);
    sequence_.store(sequence + 1, std::memory_order_relaxed);  // odd: write in progress
    std::atomic_thread_fence(std::memory_order_release);
    value_.store(value);
    sequence_.store(sequence + 2, std::memory_order_release);
  }

  // How many values have been published; a reader compares it with the last one it read to skip
  // copying an unchanged value.
  uint64_t version() const { return sequence_.load(std::memory_order_acquire) / 2; }

  // The latest published value (all bytes zero before the first publish) and its version.
  T read(uint64_t& version_out) const {
    for (;;) {
      const uint64_t before = sequence_.load(std::memory_order_acquire);
      if (before % 2 != 0) continue;
      const T value = value_.load();
      std::atomic_thread_fence(std::memory_order_acquire);
      if (sequence_.load(std::memory_order_relaxed) == before) {
        version_out = before / 2;
        return value;
      }
    }
  }

 private:
  std::atomic<uint64_t> sequence_{0};
  AtomicWords<T> value_{};
};

}  // namespace incise::devices::agent
