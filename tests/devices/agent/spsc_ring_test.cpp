// The lock-free state ring between the haptic and io threads: devices/agent/spsc_ring.h.

#include "devices/agent/spsc_ring.h"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

namespace incise::devices::agent {
namespace {

TEST(SpscRing, PopsInPushOrder) {
  SpscRing<int, 8> ring;
  int out = -1;
  EXPECT_FALSE(ring.pop(out));
  int next_pushed = 0;
  int next_popped = 0;
  // Interleave bursts that fill the ring up to its capacity with partial drains.
  for (int round = 0; round < 50; ++round) {
    for (int i = 0; i < round % 9 && next_pushed - next_popped < 8; ++i)
      ring.push(next_pushed++);
    for (int i = 0; i < round % 5 && ring.pop(out); ++i)
      EXPECT_EQ(out, next_popped++);
  }
  while (ring.pop(out))
    EXPECT_EQ(out, next_popped++);
  EXPECT_EQ(next_popped, next_pushed);
  EXPECT_EQ(ring.dropped(), 0u);
  EXPECT_EQ(ring.pushed(), static_cast<uint64_t>(next_pushed));
}

TEST(SpscRing, OverflowDropsTheOldestAndCountsThem) {
  SpscRing<int, 8> ring;
  for (int i = 1; i <= 20; ++i)
    ring.push(i);
  std::vector<int> popped;
  int out = 0;
  while (ring.pop(out))
    popped.push_back(out);
  EXPECT_EQ(popped, (std::vector<int>{13, 14, 15, 16, 17, 18, 19, 20}));  // the newest 8
  EXPECT_EQ(ring.dropped(), 12u);
  ring.push(21);
  ASSERT_TRUE(ring.pop(out));
  EXPECT_EQ(out, 21);
  EXPECT_EQ(ring.dropped(), 12u);
}

// Each value carries its index three ways, so a torn copy would show.
struct Sample {
  uint64_t index = 0;
  uint64_t tripled = 0;
  uint64_t inverted = 0;
  double as_double = 0.0;
};

TEST(SpscRing, ConcurrentProducerNeverTearsAValue) {
  SpscRing<Sample, 16> ring;  // small, so that the producer laps the consumer often
  constexpr uint64_t kCount = 300000;
  std::thread producer([&] {
    for (uint64_t i = 1; i <= kCount; ++i)
      ring.push({i, 3 * i, ~i, static_cast<double>(i)});
  });
  uint64_t popped = 0;
  uint64_t last = 0;
  Sample s;
  while (last < kCount) {
    if (!ring.pop(s)) continue;
    ++popped;
    ASSERT_EQ(s.tripled, 3 * s.index);
    ASSERT_EQ(s.inverted, ~s.index);
    ASSERT_EQ(s.as_double, static_cast<double>(s.index));
    ASSERT_GT(s.index, last);  // in order, gaps only where values were dropped
    last = s.index;
  }
  producer.join();
  EXPECT_EQ(popped + ring.dropped(), kCount);  // every value popped or counted as dropped
}

}  // namespace
}  // namespace incise::devices::agent
