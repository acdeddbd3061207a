#include "server/booking_rules.h"

namespace incise::server {

std::optional<std::string> check_slot(std::int64_t starts_at, std::int64_t ends_at,
                                      std::int64_t now, const BookingRules& rules) {
  if (ends_at <= starts_at) return "ends_at must be after starts_at";
  if (starts_at % rules.granularity_s != 0 || ends_at % rules.granularity_s != 0) {
    return "slots start and end on whole quarter hours";
  }
  const auto length = ends_at - starts_at;
  if (length < rules.min_length_s || length > rules.max_length_s) {
    return "a slot lasts from " + std::to_string(rules.min_length_s / 60) + " minutes to " +
           std::to_string(rules.max_length_s / 3600) + " hours";
  }
  // The quarter hour in progress may still be booked, so that a trainee can walk up and train.
  if (starts_at + rules.granularity_s <= now) return "starts_at is in the past";
  if (starts_at > now + rules.horizon_s) {
    return "bookings open at most " + std::to_string(rules.horizon_s / 86400) + " days ahead";
  }
  return std::nullopt;
}

}  // namespace incise::server
