#pragma once
// A trivially copyable value kept as an array of atomic 64-bit words, so that one thread may copy
// it in while another copies it out without a data race in the C++ memory model. The copy may
// be torn (some words old, some new); the seqlock-style users detect that with a version number
// and retry or discard (Boehm, "Can seqlocks get along with programming language memory
// models?", MSPC 2012). Relaxed word accesses compile to plain moves on x86-64 and AArch64.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace incise::devices::agent {

template <typename T>
class AtomicWords {
  static_assert(std::is_trivially_copyable_v<T>);
  static_assert(std::atomic<uint64_t>::is_always_lock_free);

 public:
  static constexpr std::size_t kWords = (sizeof(T) + 7) / 8;

  void store(const T& value) {
    std::array<uint64_t, kWords> words{};
    std::memcpy(words.data(), &value, sizeof(T));
    for (std::size_t i = 0; i < kWords; ++i)
      words_[i].store(words[i], std::memory_order_relaxed);
  }

  T load() const {
    std::array<uint64_t, kWords> words{};
    for (std::size_t i = 0; i < kWords; ++i)
      words[i] = words_[i].load(std::memory_order_relaxed);
    T value;
    std::memcpy(static_cast<void*>(&value), words.data(), sizeof(T));
    return value;
  }

 private:
  std::array<std::atomic<uint64_t>, kWords> words_{};
};

}  // namespace incise::devices::agent
