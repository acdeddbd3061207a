// ISO 8601 UTC text of the API: server/time_text.h.
#include "server/time_text.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>

namespace incise::server {
namespace {

constexpr std::int64_t kLastSecondOf9999 = 253402300799;  // 9999-12-31T23:59:59Z

TEST(TimeText, FormatsKnownInstants) {
  EXPECT_EQ(format_utc(0), "1970-01-01T00:00:00Z");
  EXPECT_EQ(format_utc(951782400), "2000-02-29T00:00:00Z");
  EXPECT_EQ(format_utc(1835395200), "2028-02-29T00:00:00Z");
  EXPECT_EQ(format_utc(1894003200), "2030-01-07T08:00:00Z");
  EXPECT_EQ(format_utc(kLastSecondOf9999), "9999-12-31T23:59:59Z");
}

TEST(TimeText, RandomTimesRoundTrip) {
  std::mt19937_64 rng(20261121);
  std::uniform_int_distribution<std::int64_t> any_time(0, kLastSecondOf9999);
  for (int i = 0; i < 20000; ++i) {
    const std::int64_t t = any_time(rng);
    const std::string text = format_utc(t);
    ASSERT_EQ(text.size(), 20u) << t;
    ASSERT_EQ(parse_utc(text), t) << text;
    // JavaScript's toISOString() writes zero milliseconds.
    const std::string js = text.substr(0, 19) + ".000Z";
    ASSERT_EQ(parse_utc(js), t) << js;
    ASSERT_EQ(format_utc(*parse_utc(text)), text);
  }
}

TEST(TimeText, EveryDayOfFourYearsRoundTrips) {
  // Noon of every day from 2027-01-01 to 2030-12-31, a span with one leap day.
  for (std::int64_t t = 1798761600 + 12 * 3600; t < 1924992000; t += 86400) {
    ASSERT_EQ(parse_utc(format_utc(t)), t) << format_utc(t);
  }
}

TEST(TimeText, LeapDays) {
  EXPECT_EQ(parse_utc("2028-02-29T00:00:00Z"), 1835395200);
  EXPECT_EQ(parse_utc("2028-02-29T23:59:59.000Z"), 1835395200 + 86399);
  EXPECT_EQ(parse_utc("2000-02-29T00:00:00Z"), 951782400);  // divisible by 400: leap
  EXPECT_EQ(parse_utc("2027-02-29T00:00:00Z"), std::nullopt);
  EXPECT_EQ(parse_utc("2100-02-29T00:00:00Z"), std::nullopt);  // divisible by 100 only
  EXPECT_EQ(parse_utc("2028-02-30T00:00:00Z"), std::nullopt);
  EXPECT_EQ(format_utc(1835395200 + 86400), "2028-03-01T00:00:00Z");
}

TEST(TimeText, AcceptsOnlyZeroMilliseconds) {
  EXPECT_EQ(parse_utc("2026-11-21T14:00:00.000Z"), parse_utc("2026-11-21T14:00:00Z"));
  EXPECT_EQ(parse_utc("2026-11-21T14:00:00.001Z"), std::nullopt);
  EXPECT_EQ(parse_utc("2026-11-21T14:00:00.500Z"), std::nullopt);
  EXPECT_EQ(parse_utc("2026-11-21T14:00:00.0Z"), std::nullopt);
  EXPECT_EQ(parse_utc("2026-11-21T14:00:00.000000Z"), std::nullopt);
  EXPECT_EQ(parse_utc("2026-11-21T14:00:00.000"), std::nullopt);
}

TEST(TimeText, RefusesOutOfRangeFields) {
  for (const char* text : {
           "2026-00-10T12:00:00Z",  // month 0
           "2026-13-10T12:00:00Z",  // month 13
           "2026-01-00T12:00:00Z",  // day 0
           "2026-01-32T12:00:00Z",  // day 32
           "2026-04-31T12:00:00Z",  // April has 30 days
           "2026-01-10T24:00:00Z",  // hour 24
           "2026-01-10T12:60:00Z",  // minute 60
           "2026-01-10T12:00:60Z",  // no leap seconds
           "2026-01-10T99:99:99Z",
       }) {
    EXPECT_EQ(parse_utc(text), std::nullopt) << text;
  }
}

TEST(TimeText, RefusesGarbage) {
  for (const char* text : {
           "",
           "Z",
           "2026-11-21",
           "2026-11-21T14:00:00",        // no Z
           "2026-11-21T14:00:00z",       // lower-case z
           "2026-11-21 14:00:00Z",       // space instead of T
           "2026-11-21t14:00:00Z",       // lower-case t
           "2026/11/21T14:00:00Z",       // wrong date separators
           "2026-11-21T14.00.00Z",       // wrong time separators
           "2026-11-21T14:00Z",          // no seconds
           "2026-11-21T14:00:00+00:00",  // offsets are not part of the API
           "2026-11-21T14:00:00ZZ",
           "2026-11-21T14:00:00Zx",
           " 2026-11-21T14:00:00Z",
           "2026-11-21T14:00:00Z ",
           "abcd-ef-ghTij:kl:mnZ",
           "2026-1x-21T14:00:00Z",
           "20261-1-21T14:00:00Z",
       }) {
    EXPECT_EQ(parse_utc(text), std::nullopt) << "'" << text << "'";
  }
}

// Every field is fixed-width digits: sscanf's %d also takes signs and leading spaces, which must
// not slip through.
TEST(TimeText, RefusesSignsAndSpacesInsideFields) {
  for (const char* text : {
           "+026-11-21T14:00:00Z",
           "-026-11-21T14:00:00Z",
           "2026-+1-21T14:00:00Z",
           "2026- 1-21T14:00:00Z",
           "2026-11-+1T14:00:00Z",
           "2026-11- 1T14:00:00Z",
           "2026-11-21T+4:00:00Z",
           "2026-11-21T 4:00:00Z",
           "2026-11-21T14:-0:00Z",
           "2026-11-21T14:00:+0Z",
           "2026-11-21T14:00: 0Z",
       }) {
    EXPECT_EQ(parse_utc(text), std::nullopt) << "'" << text << "'";
  }
}

}  // namespace
}  // namespace incise::server
