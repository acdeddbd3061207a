#pragma once
// Values a hostile client puts into an otherwise well-formed JSON message, for the tests of every
// place where received bytes become values: bytes that are not UTF-8, overlong and surrogate
// encodings, lone surrogate escapes, and numbers beyond a double's range. Each is placed into a
// message template with with_value().
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace incise::test {

struct HostileValue {
  std::string what;   // for test messages
  std::string token;  // JSON value text as sent (a string with its quotes, or a number)
  bool number = false;
};

inline std::vector<HostileValue> hostile_values() {
  return {
      {"a byte that is never UTF-8 (0xFF)", "\"\xff\"", false},
      {"a bare continuation byte", "\"a\x80z\"", false},
      {"an overlong two-byte '/' (C0 AF)", "\"\xc0\xaf\"", false},
      {"an overlong three-byte '/' (E0 80 AF)", "\"\xe0\x80\xaf\"", false},
      {"a surrogate encoded in UTF-8 (ED A0 80)", "\"\xed\xa0\x80\"", false},
      {"a code point past U+10FFFF (F4 90 80 80)", "\"\xf4\x90\x80\x80\"", false},
      {"a truncated sequence (E2 82)", "\"\xe2\x82\"", false},
      {"a lone high surrogate escape", R"("\ud800")", false},
      {"a lone low surrogate escape", R"("\udc00")", false},
      {"a high surrogate escape before a non-surrogate", R"("\ud800\u0041")", false},
      {"a raw 0xFF outside any string", "\xff", false},
      {"1e400", "1e400", true},
      {"-1e400", "-1e400", true},
      {"an integer of 401 digits", "1" + std::string(400, '0'), true},
  };
}

// `message` with its one '@' replaced by `token`.
inline std::string with_value(std::string_view message, std::string_view token) {
  const auto at = message.find('@');
  return std::string(message.substr(0, at)) + std::string(token) +
         std::string(message.substr(at + 1));
}

// Whether `text` is valid UTF-8, judged by nlohmann's strict serialiser (an oracle independent of
// the server's own check): it throws type_error 316 on anything else.
inline bool is_utf8(const std::string& text) {
  try {
    (void)nlohmann::json(text).dump();
    return true;
  } catch (const nlohmann::json::type_error&) {
    return false;
  }
}

}  // namespace incise::test
