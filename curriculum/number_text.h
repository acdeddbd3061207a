#pragma once
// The shortest decimal text that reads back as exactly a double, so that an error message or an
// event label names the very value (0.1 + 0.2 prints as 0.30000000000000004, not 0.3).
#include <array>
#include <charconv>
#include <string>

namespace incise::curriculum {

inline std::string shortest_text(double x) {
  std::array<char, 32> text{};
  const auto end = std::to_chars(text.data(), text.data() + text.size(), x).ptr;
  return std::string(text.data(), end);
}

}  // namespace incise::curriculum
