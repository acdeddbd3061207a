#pragma once
// The outcome of parsing text we did not write (JSON messages, scripts, command lines): a value,
// or one precise error that names where the input is wrong and how.

#include <optional>
#include <string>
#include <utility>

namespace incise::devices {

template <typename T>
struct ParseResult {
  std::optional<T> value;  // set on success
  std::string error;       // set on failure, e.g. `waypoints[2].t: must be a number, got string`

  static ParseResult success(T parsed) { return {std::move(parsed), {}}; }
  static ParseResult failure(std::string why) { return {std::nullopt, std::move(why)}; }

  explicit operator bool() const { return value.has_value(); }
};

}  // namespace incise::devices
