#pragma once
// The agent's log: one line per event on stderr, prefixed so that it stands out in a station's
// journal next to other programs.

#include <chrono>
#include <cstdio>
#include <string>
#include <string_view>

namespace incise::devices::agent {

inline void log_line(std::string_view message) {
  std::string line = "incise-agent: ";
  line.append(message);
  line.push_back('\n');
  // One write per line, so that lines from concurrent writers never interleave.
  std::fwrite(line.data(), 1, line.size(), stderr);
  std::fflush(stderr);
}

// "0.25 s", "5 s", "12.3 s": centisecond precision without trailing zeros.
inline std::string format_seconds(std::chrono::duration<double> duration) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.2f", duration.count());
  std::string text = buffer;
  text.erase(text.find_last_not_of('0') + 1);
  if (text.back() == '.') text.pop_back();
  return text + " s";
}

}  // namespace incise::devices::agent
