// A viewer's control messages on the view WebSocket: parse_view_message in server/view_message.h,
// for live views and replays, with well-formed, malformed and hostile messages.
#include "server/view_message.h"

#include <gtest/gtest.h>

#include <string>

#include "tests/support/hostile_json.h"

namespace incise::server {
namespace {

using Type = ViewMessage::Type;

ViewMessage accepted(const std::string& text, std::int64_t issued = 10, bool replay = true) {
  const auto result = parse_view_message(text, issued, replay);
  EXPECT_TRUE(result.message) << text << ": " << result.error;
  EXPECT_TRUE(result.error.empty());
  return result.message.value_or(ViewMessage{});
}

std::string refused(const std::string& text, std::int64_t issued = 10, bool replay = true) {
  const auto result = parse_view_message(text, issued, replay);
  EXPECT_FALSE(result.message) << text;
  EXPECT_TRUE(test::is_utf8(result.error)) << text;
  EXPECT_LE(result.error.size(), 123u) << text;
  return result.error;
}

TEST(ViewMessage, EachTypeIsReadWithItsFields) {
  const auto ack = accepted(R"({"type": "ack", "frame": 7})");
  EXPECT_EQ(ack.type, Type::ack);
  EXPECT_EQ(ack.frame, 7);
  const auto configure = accepted(R"({"type": "configure", "fps": 12, "width": 320})");
  EXPECT_EQ(configure.type, Type::configure);
  EXPECT_EQ(configure.fps, 12);
  EXPECT_EQ(configure.width, 320);
  EXPECT_FALSE(configure.height);
  EXPECT_EQ(accepted(R"({"type": "play"})").type, Type::play);
  EXPECT_EQ(accepted(R"({"type": "pause"})").type, Type::pause);
  const auto speed = accepted(R"({"type": "speed", "value": 0.25})");
  EXPECT_EQ(speed.type, Type::speed);
  EXPECT_EQ(speed.value, 0.25);
  const auto seek = accepted(R"({"type": "seek", "t": 12.5})");
  EXPECT_EQ(seek.type, Type::seek);
  EXPECT_EQ(seek.value, 12.5);
  EXPECT_EQ(accepted(R"({"type": "configure", "view": "outside"})").outside, true);
  EXPECT_EQ(accepted(R"({"type": "configure", "view": "scope", "fps": 5})").outside, false);
  EXPECT_FALSE(configure.outside);
  // An integral double is an integer.
  EXPECT_EQ(accepted(R"({"type": "ack", "frame": 3.0})").frame, 3);
}

TEST(ViewMessage, ReplayControlsAreUnknownOnALiveView) {
  for (const char* type : {"play", "pause", "speed", "seek"}) {
    const std::string text = std::string(R"({"type": ")") + type + R"(", "value": 1, "t": 1})";
    EXPECT_EQ(refused(text, 10, false), std::string("unknown message type \"") + type + "\"");
    accepted(text, 10, true);
  }
}

TEST(ViewMessage, MalformedMessagesAreRefusedWithTheReason) {
  EXPECT_EQ(refused(R"({"type": "warp"})"), "unknown message type \"warp\"");
  EXPECT_EQ(refused(R"([1, 2])"), "a message must be an object with a string \"type\"");
  EXPECT_EQ(refused(R"({"type": 5})"), "a message must be an object with a string \"type\"");
  EXPECT_EQ(refused(R"({"frame": 1})"), "a message must be an object with a string \"type\"");
  EXPECT_EQ(refused(R"({"type": "ack"})"), "ack needs \"frame\"");
  EXPECT_EQ(refused(R"({"type": "speed"})"), "speed needs \"value\"");
  EXPECT_EQ(refused(R"({"type": "speed", "value": 10})"), "speed: \"value\" must be in [0.25, 4]");
  EXPECT_EQ(refused(R"({"type": "speed", "value": 0.2})"), "speed: \"value\" must be in [0.25, 4]");
  EXPECT_EQ(accepted(R"({"type": "speed", "value": 4})").value, 4.0);
  EXPECT_EQ(refused(R"({"type": "seek"})"), "seek needs \"t\"");
  EXPECT_EQ(refused(R"({"type": "seek", "t": "soon"})"), "seek: \"t\" must be a number");
  // Only frames that were sent can be acknowledged: a larger number would switch off flow control.
  EXPECT_EQ(refused(R"({"type": "ack", "frame": 11})"),
            "ack: \"frame\" must be an integer in [1, 10]");
  EXPECT_EQ(refused(R"({"type": "ack", "frame": 1.5})"),
            "ack: \"frame\" must be an integer in [1, 10]");
  EXPECT_EQ(refused(R"({"type": "configure", "fps": 61})"),
            "configure: \"fps\" must be an integer in [1, 60]");
  EXPECT_EQ(refused(R"({"type": "configure", "width": 1e300})"),
            "configure: \"width\" must be an integer in [160, 1280]");
  EXPECT_EQ(refused(R"({"type": "configure", "view": "inside"})"),
            "configure: \"view\" must be \"scope\" or \"outside\"");
  EXPECT_EQ(refused(R"({"type": "configure", "view": 1})"),
            "configure: \"view\" must be \"scope\" or \"outside\"");
  EXPECT_TRUE(refused("{\"type\": \"ack\"").starts_with("malformed JSON: parse error at line 1"));
  // A long unknown type is cut to fit, at a whole character.
  const auto long_type =
      refused(R"({"type": ")" + std::string(30, 'x') + std::string(20, '\xC3') + R"("})");
  EXPECT_TRUE(long_type.starts_with("malformed JSON: ")) << long_type;  // C3 alone is not UTF-8
  const auto cut = refused(R"({"type": ")" + std::string(39, 'x') + "\xC3\xBC\xC3\xBC" + R"("})");
  EXPECT_EQ(cut, "unknown message type \"" + std::string(37, 'x') + "...\"");
}

TEST(ViewMessage, HostileValuesInEveryFieldAreRefusedWithoutThrowing) {
  const char* const templates[] = {
      R"({"type": "ack", "frame": @})",
      R"({"type": "configure", "fps": @})",
      R"({"type": "configure", "width": @})",
      R"({"type": "configure", "height": @})",
      R"({"type": "speed", "value": @})",
      R"({"type": "seek", "t": @})",
      R"({"type": @})",
      R"({"type": "play", "extra": [@]})",
  };
  for (const auto& value : test::hostile_values()) {
    for (const char* message : templates) {
      const auto text = test::with_value(message, value.token);
      ViewMessageResult result;
      ASSERT_NO_THROW(result = parse_view_message(text, 10, true)) << value.what;
      EXPECT_FALSE(result.message) << value.what << " in " << text;
      EXPECT_TRUE(result.error.starts_with("malformed JSON: ")) << result.error;
      EXPECT_TRUE(test::is_utf8(result.error)) << value.what;
      EXPECT_LE(result.error.size(), 123u);
    }
  }
  EXPECT_EQ(refused(R"({"type": "ack", "frame": -1e400})"),
            "malformed JSON: number overflow parsing '-1e400'");
  EXPECT_EQ(refused(R"({"type": "configure", "fps": 1e400})"),
            "malformed JSON: number overflow parsing '1e400'");
  // Deep nesting in a message is refused before it is parsed.
  EXPECT_EQ(
      refused(R"({"type": "play", "x": )" + std::string(100, '[') + std::string(100, ']') + "}"),
      "malformed JSON: nested deeper than 8 levels");
}

}  // namespace
}  // namespace incise::server
