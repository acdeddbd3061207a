#include "devices/agent/loop_stats.h"

#include <algorithm>
#include <cstdlib>

namespace incise::devices::agent {
namespace {

constexpr std::size_t kMicrosecondBins = 20000;  // 0 .. 20 ms at 1 us

// Nearest microsecond, for a non-negative duration.
uint64_t round_us(int64_t ns) {
  return static_cast<uint64_t>((ns + 500) / 1000);
}

}  // namespace

LoopStats::LoopStats(std::chrono::nanoseconds nominal_period)
    : nominal_(nominal_period), period_us_(1, kMicrosecondBins), jitter_us_(1, kMicrosecondBins) {}

void LoopStats::record_period(std::chrono::nanoseconds period) {
  const int64_t ns = std::max<int64_t>(period.count(), 0);
  const auto jitter_ns = static_cast<uint64_t>(std::llabs(ns - nominal_.count()));
  period_us_.add(round_us(ns));
  jitter_us_.add(round_us(static_cast<int64_t>(jitter_ns)));
  if (jitter_ns > max_jitter_ns_.load(std::memory_order_relaxed)) {
    max_jitter_ns_.store(jitter_ns, std::memory_order_relaxed);
  }
  bump(total_ns_, static_cast<uint64_t>(ns));
}

LoopSummary LoopStats::summary() const {
  LoopSummary s;
  s.periods = period_us_.count();
  const uint64_t total_ns = total_ns_.load(std::memory_order_relaxed);
  s.rate_hz =
      total_ns > 0 ? static_cast<double>(s.periods) * 1e9 / static_cast<double>(total_ns) : 0.0;
  s.period_p50_us = static_cast<double>(period_us_.percentile(50));
  s.period_p99_us = static_cast<double>(period_us_.percentile(99));
  s.jitter_p99_us = static_cast<double>(jitter_us_.percentile(99));
  s.max_jitter_us = static_cast<double>(max_jitter_ns_.load(std::memory_order_relaxed)) / 1000.0;
  s.overruns = overruns_.load(std::memory_order_relaxed);
  return s;
}

}  // namespace incise::devices::agent
