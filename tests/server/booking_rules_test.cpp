// Which slots may be booked: server/booking_rules.h.
#include "server/booking_rules.h"

#include <gtest/gtest.h>

#include <cstdint>

namespace incise::server {
namespace {

constexpr std::int64_t kMinute = 60;
constexpr std::int64_t kQuarter = 15 * kMinute;
constexpr std::int64_t kHour = 3600;
constexpr std::int64_t kDay = 86400;
constexpr std::int64_t kNow = 1894003200;  // 2030-01-07T08:00:00Z, on a quarter hour
constexpr std::int64_t kStart = kNow + kDay;

const std::string kLengthMessage = "a slot lasts from 15 minutes to 4 hours";
const std::string kQuarterMessage = "slots start and end on whole quarter hours";

TEST(BookingRules, ShortestAndLongestSlotsAreAccepted) {
  EXPECT_EQ(check_slot(kStart, kStart + 15 * kMinute, kNow), std::nullopt);
  EXPECT_EQ(check_slot(kStart, kStart + 4 * kHour, kNow), std::nullopt);
}

TEST(BookingRules, SlotsOutsideTheLengthsAreRefused) {
  // With the default quarter-hour grid, 14 and 241 minutes already miss the grid.
  EXPECT_EQ(check_slot(kStart, kStart + 14 * kMinute, kNow), kQuarterMessage);
  EXPECT_EQ(check_slot(kStart, kStart + 241 * kMinute, kNow), kQuarterMessage);
  EXPECT_EQ(check_slot(kStart, kStart + 4 * kHour + kQuarter, kNow), kLengthMessage);
  // On a one-minute grid the length rule itself decides, at its exact boundaries.
  BookingRules minutes;
  minutes.granularity_s = kMinute;
  EXPECT_EQ(check_slot(kStart, kStart + 14 * kMinute, kNow, minutes), kLengthMessage);
  EXPECT_EQ(check_slot(kStart, kStart + 15 * kMinute, kNow, minutes), std::nullopt);
  EXPECT_EQ(check_slot(kStart, kStart + 240 * kMinute, kNow, minutes), std::nullopt);
  EXPECT_EQ(check_slot(kStart, kStart + 241 * kMinute, kNow, minutes), kLengthMessage);
}

TEST(BookingRules, EndMustFollowStart) {
  EXPECT_EQ(check_slot(kStart, kStart, kNow), "ends_at must be after starts_at");
  EXPECT_EQ(check_slot(kStart, kStart - kQuarter, kNow), "ends_at must be after starts_at");
}

TEST(BookingRules, SlotsOffTheQuarterHourGridAreRefused) {
  for (const std::int64_t offset : {std::int64_t{1}, kMinute, 7 * kMinute, 14 * kMinute + 59}) {
    EXPECT_EQ(check_slot(kStart + offset, kStart + offset + kHour, kNow), kQuarterMessage)
        << offset;
    EXPECT_EQ(check_slot(kStart, kStart + kHour + offset, kNow), kQuarterMessage) << offset;
  }
  EXPECT_EQ(check_slot(kStart + 30 * kMinute, kStart + 45 * kMinute, kNow), std::nullopt);
}

TEST(BookingRules, PastSlotsAreRefused) {
  EXPECT_EQ(check_slot(kNow - kQuarter, kNow + kQuarter, kNow), "starts_at is in the past");
  EXPECT_EQ(check_slot(kNow - kDay, kNow - kDay + kHour, kNow), "starts_at is in the past");
  // The quarter hour in progress may be booked (a walk-up slot), up to its last second.
  EXPECT_EQ(check_slot(kNow, kNow + kQuarter, kNow), std::nullopt);
  EXPECT_EQ(check_slot(kNow, kNow + kQuarter, kNow + kQuarter - 1), std::nullopt);
  EXPECT_EQ(check_slot(kNow, kNow + kHour, kNow + kQuarter), "starts_at is in the past");
}

TEST(BookingRules, SlotsBeyondTheHorizonAreRefused) {
  const std::int64_t horizon = BookingRules{}.horizon_s;
  EXPECT_EQ(horizon, 180 * kDay);
  EXPECT_EQ(check_slot(kNow + horizon, kNow + horizon + kHour, kNow), std::nullopt);
  EXPECT_EQ(check_slot(kNow + horizon + kQuarter, kNow + horizon + kHour, kNow),
            "bookings open at most 180 days ahead");
}

// Over a grid of starts and lengths, a slot is accepted exactly when every rule holds.
TEST(BookingRules, AcceptsExactlyTheSlotsThatFollowEveryRule) {
  for (std::int64_t start = kNow - kHour; start <= kNow + 2 * kHour; start += 5 * kMinute) {
    for (std::int64_t length = 0; length <= 5 * kHour; length += 5 * kMinute) {
      const bool on_grid = start % kQuarter == 0 && length % kQuarter == 0;
      const bool ok = on_grid && length >= kQuarter && length <= 4 * kHour && start >= kNow;
      EXPECT_EQ(!check_slot(start, start + length, kNow).has_value(), ok)
          << "start " << start - kNow << " s from now, length " << length << " s";
    }
  }
}

}  // namespace
}  // namespace incise::server
