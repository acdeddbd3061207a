// The parser of REST bodies and view and replay messages: server/json_input.h. Every error
// nlohmann's parser can raise comes back as a kind and a short valid message, never as an
// exception.
#include "server/json_input.h"

#include <gtest/gtest.h>

#include <string>

#include "tests/support/hostile_json.h"

namespace incise::server {
namespace {

TEST(JsonInput, ParsesWhatIsValid) {
  const auto input = parse_json_input(R"({"a": [1, 2.5, "caf\u00e9", {"b": null}], "c": -0})");
  ASSERT_TRUE(input) << input.message;
  EXPECT_EQ(input.value["a"][2], "caf\xC3\xA9");
  EXPECT_TRUE(input.message.empty());
  // The largest finite doubles still parse.
  EXPECT_TRUE(parse_json_input("[1.7976931348623157e308, -1.7976931348623157e308, 1e-400]"));
}

TEST(JsonInput, EveryHostileValueIsAnErrorOfItsKind) {
  for (const auto& value : test::hostile_values()) {
    for (const char* message : {"@", R"({"type": "configure", "fps": @})", "[[1, @]]"}) {
      const auto text = test::with_value(message, value.token);
      JsonInput input;
      ASSERT_NO_THROW(input = parse_json_input(text)) << value.what;
      EXPECT_FALSE(input) << value.what;
      EXPECT_EQ(input.error, value.number ? JsonInputError::out_of_range : JsonInputError::syntax)
          << value.what << ": " << input.message;
      EXPECT_TRUE(input.value.is_discarded());
      EXPECT_FALSE(input.message.empty());
      // The message quotes what was read; it must be valid UTF-8, short, and unprefixed.
      EXPECT_TRUE(test::is_utf8(input.message)) << value.what;
      EXPECT_LE(input.message.size(), 160u) << input.message;
      EXPECT_EQ(input.message.find("[json.exception"), std::string::npos) << input.message;
    }
  }
  EXPECT_EQ(parse_json_input("1e400").message, "number overflow parsing '1e400'");
}

TEST(JsonInput, NestingBeyondTheLimitIsRefusedBeforeParsing) {
  const auto nested = [](int depth) { return std::string(depth, '[') + std::string(depth, ']'); };
  EXPECT_TRUE(parse_json_input(nested(kMaxJsonDepth)));
  const auto deep = parse_json_input(nested(kMaxJsonDepth + 1));
  EXPECT_EQ(deep.error, JsonInputError::too_deep);
  EXPECT_EQ(deep.message, "nested deeper than 64 levels");
  // A body of the REST limit's size made of brackets alone.
  EXPECT_EQ(parse_json_input(nested(32 * 1024)).error, JsonInputError::too_deep);
  // Brackets inside strings, escaped quotes included, do not count.
  const std::string in_string = "[\"" + std::string(200, '[') + "\\\"" + "\"]";
  EXPECT_TRUE(parse_json_input(in_string)) << parse_json_input(in_string).message;
  EXPECT_TRUE(parse_json_input(nested(3), 3));
  EXPECT_FALSE(parse_json_input(R"({"a": {"b": {"c": {}}}})", 3));
}

}  // namespace
}  // namespace incise::server
