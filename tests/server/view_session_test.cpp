// The viewer's query string on the view WebSocket: parse_view_query in server/view_session.h.
#include <gtest/gtest.h>

#include <string>

#include "server/view_session.h"

namespace incise::server {
namespace {

constexpr ViewRequest kDefaults;  // 30 fps, 640 x 480

void expect_request(const std::string& target, int fps, int width, int height) {
  const auto r = parse_view_query(target);
  EXPECT_EQ(r.fps, fps) << target;
  EXPECT_EQ(r.width, width) << target;
  EXPECT_EQ(r.height, height) << target;
}

TEST(ParseViewQuery, DefaultsWithoutAQuery) {
  EXPECT_EQ(kDefaults.fps, 30);
  EXPECT_EQ(kDefaults.width, 640);
  EXPECT_EQ(kDefaults.height, 480);
  for (const char* target : {"/api/live/7/view", "/api/live/7/view?", "", "?", "?&&&"})
    expect_request(target, 30, 640, 480);
}

TEST(ParseViewQuery, ValuesInRangeAreTaken) {
  expect_request("/api/live/7/view?fps=12&width=800&height=600", 12, 800, 600);
  expect_request("/api/replays/3/view?height=600&fps=12&width=800", 12, 800, 600);
  expect_request("/v?width=1024", 30, 1024, 480);
}

TEST(ParseViewQuery, EachParameterIsClampedAtBothEnds) {
  // fps in [1, 60]
  expect_request("/v?fps=1", 1, 640, 480);
  expect_request("/v?fps=0", 1, 640, 480);
  expect_request("/v?fps=-20", 1, 640, 480);
  expect_request("/v?fps=60", 60, 640, 480);
  expect_request("/v?fps=61", 60, 640, 480);
  expect_request("/v?fps=100000", 60, 640, 480);
  // width in [160, 1280]
  expect_request("/v?width=160", 30, 160, 480);
  expect_request("/v?width=159", 30, 160, 480);
  expect_request("/v?width=0", 30, 160, 480);
  expect_request("/v?width=1280", 30, 1280, 480);
  expect_request("/v?width=1281", 30, 1280, 480);
  // height in [120, 960]
  expect_request("/v?height=120", 30, 640, 120);
  expect_request("/v?height=119", 30, 640, 120);
  expect_request("/v?height=-1", 30, 640, 120);
  expect_request("/v?height=960", 30, 640, 960);
  expect_request("/v?height=961", 30, 640, 960);
  // all three at once, low and high
  expect_request("/v?fps=0&width=1&height=1", 1, 160, 120);
  expect_request("/v?fps=999&width=99999&height=99999", 60, 1280, 960);
}

TEST(ParseViewQuery, GarbageFallsBackToTheDefault) {
  for (const char* value :
       {"", "abc", "12x", "x12", "1.5", "+5", " 5", "5 ", "0x10", "--1", "99999999999999999999"}) {
    const std::string v = value;
    expect_request("/v?fps=" + v, 30, 640, 480);
    expect_request("/v?width=" + v, 30, 640, 480);
    expect_request("/v?height=" + v, 30, 640, 480);
  }
  // A bad value spoils only its own parameter.
  expect_request("/v?fps=abc&width=800&height=zz", 30, 800, 480);
  // A key without '=' is no value.
  expect_request("/v?fps&width=800", 30, 800, 480);
}

TEST(ParseViewQuery, UnrelatedParametersAreIgnored) {
  expect_request("/v?token=abc&fps=20&x=1&width=320&frame=9&height=240&y", 20, 320, 240);
  // Only whole keys match.
  expect_request("/v?xfps=10&fpsx=10&widths=200&Height=200", 30, 640, 480);
  // The path is not part of the query.
  expect_request("/fps=10/view?width=800", 30, 800, 480);
}

TEST(ParseViewQuery, TheOutsideViewIsAskedForByItsWholeKeyAndValue) {
  EXPECT_FALSE(kDefaults.outside);
  EXPECT_TRUE(parse_view_query("/v?fps=10&view=outside").outside);
  for (const char* target : {"/v?view=scope", "/v?xview=outside", "/v?view=outsides",
                             "/view=outside", "/v?view=Outside", "/v?view"}) {
    EXPECT_FALSE(parse_view_query(target).outside) << target;
  }
}

}  // namespace
}  // namespace incise::server
