#pragma once
// ISO 8601 UTC timestamps as used by the API ("2026-11-21T14:00:00Z"), from and to Unix seconds.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace incise::server {

std::string format_utc(std::int64_t unix_seconds);
// Accepts "YYYY-MM-DDTHH:MM:SSZ" (also with ".000" fractions of zero, as JavaScript's
// toISOString() writes them). nullopt for anything else, including impossible dates.
std::optional<std::int64_t> parse_utc(std::string_view text);

}  // namespace incise::server
