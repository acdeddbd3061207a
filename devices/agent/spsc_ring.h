#pragma once
// A fixed-capacity single-producer single-consumer ring that never makes the producer wait or
// fail: the haptic thread (producer) pushes every k-th device state, the io thread (consumer)
// pops them for the network. If the consumer falls N behind, the producer overwrites the oldest
// value and the consumer counts it as dropped: a stalled link loses old states, never new ones,
// and never slows the haptic loop.
//
// Lock-free and allocation-free. Each slot is copied as atomic words (AtomicWords); the producer
// announces which index it is about to write (claimed_) before writing it, so a consumer that
// copied a slot while it was being overwritten sees that and skips ahead instead of returning a
// torn value.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

#include "devices/agent/atomic_words.h"

namespace incise::devices::agent {

template <typename T, std::size_t N>
class SpscRing {
  static_assert(N >= 2 && (N & (N - 1)) == 0, "capacity must be a power of two");

 public:
  static constexpr std::size_t capacity() { return N; }

  // Producer only. Wait-free.
  void push(const T& value) {
    const uint64_t index = head_.load(std::memory_order_relaxed);
    claimed_.store(index + 1, std::memory_order_relaxed);
    // Orders the claim before the slot's words: a consumer that reads any new word sees the claim.
    std::atomic_thread_fence(std::memory_order_release);
    slots_[index % N].store(value);
    head_.store(index + 1, std::memory_order_release);
  }

  // Consumer only. Copies the oldest value not yet popped into out and returns true, or returns
  // false if there is none. Values overwritten before they were popped are counted in dropped().
  bool pop(T& out) {
    for (;;) {
      const uint64_t head = head_.load(std::memory_order_acquire);
      if (next_ == head) return false;
      if (head - next_ > N) skip_to(head - N);
      const T value = slots_[next_ % N].load();
      std::atomic_thread_fence(std::memory_order_acquire);
      // claimed = 1 + the index being (or last) written; index next_ + N shares our slot.
      const uint64_t claimed = claimed_.load(std::memory_order_relaxed);
      if (claimed > next_ + N) {
        skip_to(claimed - N);  // the oldest index that the producer has not started to overwrite
        continue;
      }
      ++next_;
      out = value;
      return true;
    }
  }

  // Consumer only: values lost to overwriting so far.
  uint64_t dropped() const { return dropped_; }

  // Any thread: values pushed so far.
  uint64_t pushed() const { return head_.load(std::memory_order_relaxed); }

 private:
  void skip_to(uint64_t index) {
    dropped_ += index - next_;
    next_ = index;
  }

  // Producer-written indices, apart from the consumer's state to avoid false sharing.
  alignas(64) std::atomic<uint64_t> head_{0};  // values published
  std::atomic<uint64_t> claimed_{0};           // 1 + the index being written
  alignas(64) uint64_t next_ = 0;              // consumer: the next index to pop
  uint64_t dropped_ = 0;                       // consumer
  alignas(64) std::array<AtomicWords<T>, N> slots_{};
};

}  // namespace incise::devices::agent
