// Fixed-bin histograms and the haptic loop's statistics: devices/agent/histogram.h,
// devices/agent/loop_stats.h.

#include "devices/agent/loop_stats.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "devices/agent/histogram.h"

namespace incise::devices::agent {
namespace {

using std::chrono::microseconds;
using std::chrono::nanoseconds;

TEST(Histogram, NearestRankPercentilesOfAKnownSequence) {
  std::vector<uint64_t> values(100);
  for (uint64_t i = 0; i < 100; ++i)
    values[i] = i + 1;  // 1 .. 100
  std::shuffle(values.begin(), values.end(), std::mt19937(3));
  Histogram h(1, 1000);
  EXPECT_EQ(h.percentile(50), 0u);  // empty
  for (uint64_t v : values)
    h.add(v);
  EXPECT_EQ(h.count(), 100u);
  EXPECT_EQ(h.percentile(50), 50u);
  EXPECT_EQ(h.percentile(99), 99u);
  EXPECT_EQ(h.percentile(99.5), 100u);
  EXPECT_EQ(h.percentile(100), 100u);
  EXPECT_EQ(h.percentile(1), 1u);
  EXPECT_EQ(h.max(), 100u);
}

TEST(Histogram, WideBinsRoundDownAndOverflowReadsAsMax) {
  Histogram h(10, 5);  // [0, 10) .. [40, 50), then overflow
  for (uint64_t v : {3, 17, 18, 45, 49, 120, 700})
    h.add(v);
  EXPECT_EQ(h.percentile(10), 0u);    // rank 1: 3
  EXPECT_EQ(h.percentile(30), 10u);   // rank 3: 18
  EXPECT_EQ(h.percentile(70), 40u);   // rank 5: 49
  EXPECT_EQ(h.percentile(80), 700u);  // rank 6: in the overflow bin
  EXPECT_EQ(h.max(), 700u);
}

TEST(LoopStats, SummaryOfASyntheticPeriodSequence) {
  LoopStats stats(microseconds(1000));
  std::vector<nanoseconds> periods(98, microseconds(1000));
  periods.push_back(microseconds(1200));
  periods.push_back(microseconds(700));
  std::shuffle(periods.begin(), periods.end(), std::mt19937(5));
  for (nanoseconds p : periods)
    stats.record_period(p);
  stats.record_overrun();
  const LoopSummary s = stats.summary();
  EXPECT_EQ(s.periods, 100u);
  EXPECT_DOUBLE_EQ(s.rate_hz, 100.0 / 0.0999);  // 100 periods in 99.9 ms
  EXPECT_EQ(s.period_p50_us, 1000.0);
  EXPECT_EQ(s.period_p99_us, 1000.0);  // sorted: 700, 98 x 1000, 1200; the 99th is 1000
  EXPECT_EQ(s.jitter_p99_us, 200.0);   // jitters 98 x 0, 200, 300
  EXPECT_EQ(s.max_jitter_us, 300.0);
  EXPECT_EQ(s.overruns, 1u);
}

TEST(LoopStats, PercentilesResolveOneMicrosecond) {
  LoopStats stats(microseconds(1000));
  // 990 .. 1009 us, five times each, in nanoseconds with sub-microsecond noise that rounds away.
  for (int repeat = 0; repeat < 5; ++repeat) {
    for (int us = 990; us < 1010; ++us)
      stats.record_period(nanoseconds(us * 1000 + (repeat - 2) * 100));
  }
  const LoopSummary s = stats.summary();
  EXPECT_EQ(s.period_p50_us, 999.0);        // rank 50 of 100: the last of 990..999
  EXPECT_EQ(s.period_p99_us, 1009.0);       // rank 99
  EXPECT_EQ(s.jitter_p99_us, 10.0);         // |990 - 1000|
  EXPECT_DOUBLE_EQ(s.max_jitter_us, 10.2);  // exact, from nanoseconds: 990 us - 200 ns
  EXPECT_NEAR(s.rate_hz, 1e6 / 999.5, 1e-9);
}

}  // namespace
}  // namespace incise::devices::agent
