#pragma once
// Timing statistics of the haptic loop: the period between consecutive tick starts in a 1 us bin
// histogram (0..20 ms, longer ones in an overflow bin), the jitter |period - nominal| likewise,
// the largest jitter exactly, and the overruns (ticks whose deadline had already passed when the
// previous tick finished).
//
// Written by the haptic thread with no allocation and no locked instruction; read by any thread
// (see Histogram).

#include <atomic>
#include <chrono>
#include <cstdint>

#include "devices/agent/histogram.h"

namespace incise::devices::agent {

struct LoopSummary {
  uint64_t periods = 0;        // tick periods measured
  double rate_hz = 0.0;        // periods / their total duration
  double period_p50_us = 0.0;  // median tick period [us], to 1 us
  double period_p99_us = 0.0;
  double jitter_p99_us = 0.0;  // 99th percentile of |period - nominal| [us], to 1 us
  double max_jitter_us = 0.0;  // largest |period - nominal| [us], exact
  uint64_t overruns = 0;
};

class LoopStats {
 public:
  explicit LoopStats(std::chrono::nanoseconds nominal_period = std::chrono::milliseconds(1));

  // Haptic thread only.
  void record_period(std::chrono::nanoseconds period);
  void record_overrun() { bump(overruns_); }

  LoopSummary summary() const;

 private:
  static void bump(std::atomic<uint64_t>& counter, uint64_t by = 1) {
    counter.store(counter.load(std::memory_order_relaxed) + by, std::memory_order_relaxed);
  }

  std::chrono::nanoseconds nominal_;
  Histogram period_us_;
  Histogram jitter_us_;
  std::atomic<uint64_t> max_jitter_ns_{0};
  std::atomic<uint64_t> total_ns_{0};
  std::atomic<uint64_t> overruns_{0};
};

}  // namespace incise::devices::agent
