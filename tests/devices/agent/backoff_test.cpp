// Reconnect delays: devices/agent/backoff.h.

#include "devices/agent/backoff.h"

#include <gtest/gtest.h>

#include <vector>

namespace incise::devices::agent {
namespace {

using std::chrono::milliseconds;

TEST(Backoff, DoublesFromAQuarterSecondUpToFiveSeconds) {
  Backoff backoff;
  std::vector<milliseconds> delays;
  for (int i = 0; i < 8; ++i)
    delays.push_back(backoff.next());
  const std::vector<milliseconds> expected = {
      milliseconds(250),  milliseconds(500),  milliseconds(1000), milliseconds(2000),
      milliseconds(4000), milliseconds(5000), milliseconds(5000), milliseconds(5000)};
  EXPECT_EQ(delays, expected);
}

TEST(Backoff, ResetStartsOver) {
  Backoff backoff;
  backoff.next();
  backoff.next();
  backoff.reset();
  EXPECT_EQ(backoff.next(), milliseconds(250));
  EXPECT_EQ(backoff.next(), milliseconds(500));
}

}  // namespace
}  // namespace incise::devices::agent
