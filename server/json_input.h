#pragma once
// The one way the server turns bytes a client sent (a REST body, a view or replay message) into
// JSON. It never throws: every error nlohmann's parser can raise (syntax errors, which include
// invalid UTF-8 and lone surrogate escapes, and numbers beyond a double's range) comes back as a
// kind and a message that is valid UTF-8 and at most 160 bytes.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace incise::server {

enum class JsonInputError {
  none,
  syntax,        // not JSON: nlohmann's parse_error (bad syntax, invalid UTF-8, lone surrogates)
  out_of_range,  // a number too large for a double, such as 1e400 (nlohmann's out_of_range 406)
  too_deep,      // arrays and objects nested deeper than the limit
};

struct JsonInput {
  nlohmann::json value;  // discarded unless error == none
  JsonInputError error = JsonInputError::none;
  std::string message;  // "" when error == none; else e.g. "number overflow parsing '1e400'"

  explicit operator bool() const { return error == JsonInputError::none; }
};

// Arrays and objects deeper than this are refused before parsing: nlohmann parses iteratively,
// but copying, comparing and serialising a value recurse once per level.
inline constexpr int kMaxJsonDepth = 64;

JsonInput parse_json_input(std::string_view bytes, int max_depth = kMaxJsonDepth);

}  // namespace incise::server
