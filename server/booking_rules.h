#pragma once
// Which slots may be booked, independent of what is already booked (that is the repository's
// conflict check). Plain logic, unit-tested directly.
#include <cstdint>
#include <optional>
#include <string>

namespace incise::server {

struct BookingRules {
  std::int64_t granularity_s = 15 * 60;  // slots start and end on quarter hours
  std::int64_t min_length_s = 15 * 60;
  std::int64_t max_length_s = 4 * 3600;
  std::int64_t horizon_s = 180 * 24 * 3600;  // how far ahead one may book
};

// nullopt if the slot [starts_at, ends_at) is bookable at `now`; otherwise why not.
std::optional<std::string> check_slot(std::int64_t starts_at, std::int64_t ends_at,
                                      std::int64_t now, const BookingRules& rules = {});

}  // namespace incise::server
