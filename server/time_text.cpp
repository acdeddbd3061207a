#include "server/time_text.h"

#include <chrono>
#include <cstdio>

namespace incise::server {

std::string format_utc(std::int64_t unix_seconds) {
  using namespace std::chrono;
  const sys_seconds t{seconds{unix_seconds}};
  const auto day = floor<days>(t);
  const year_month_day ymd{day};
  const hh_mm_ss hms{t - day};
  char out[32];
  std::snprintf(out, sizeof out, "%04d-%02u-%02uT%02d:%02d:%02dZ", static_cast<int>(ymd.year()),
                static_cast<unsigned>(ymd.month()), static_cast<unsigned>(ymd.day()),
                static_cast<int>(hms.hours().count()), static_cast<int>(hms.minutes().count()),
                static_cast<int>(hms.seconds().count()));
  return out;
}

std::optional<std::int64_t> parse_utc(std::string_view text) {
  if (text.size() == 24 && text.substr(19) == ".000Z") {
    text = text.substr(0, 19);
  } else if (text.size() == 20 && text.back() == 'Z') {
    text = text.substr(0, 19);
  } else {
    return std::nullopt;
  }
  // Exactly "DDDD-DD-DDTDD:DD:DD": sscanf alone would also take signs and spaces inside fields.
  for (std::size_t i = 0; i < text.size(); ++i) {
    const bool separator = i == 4 || i == 7 || i == 10 || i == 13 || i == 16;
    if (!separator && (text[i] < '0' || text[i] > '9')) return std::nullopt;
  }
  int y, mo, d, h, mi, s;
  char tail;
  const std::string copy(text);
  if (std::sscanf(copy.c_str(), "%4d-%2d-%2dT%2d:%2d:%2d%c", &y, &mo, &d, &h, &mi, &s, &tail) != 6)
    return std::nullopt;
  if (copy[4] != '-' || copy[7] != '-' || copy[10] != 'T' || copy[13] != ':' || copy[16] != ':')
    return std::nullopt;
  using namespace std::chrono;
  const year_month_day ymd{year{y}, month{static_cast<unsigned>(mo)},
                           day{static_cast<unsigned>(d)}};
  if (!ymd.ok() || h > 23 || mi > 59 || s > 59 || h < 0 || mi < 0 || s < 0) return std::nullopt;
  const auto t = sys_days{ymd} + hours{h} + minutes{mi} + seconds{s};
  return duration_cast<seconds>(t.time_since_epoch()).count();
}

}  // namespace incise::server
