#pragma once
// Bookings of station slots. A station slot and a person can each hold only one active booking
// at a time (a completed one no longer counts: its session ended and freed the rest); the check and
// the insert run in one IMMEDIATE transaction, so two concurrent requests cannot both win.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "db/database.h"
#include "db/db_error.h"
#include "db/trainee_scope.h"

namespace incise::db {

struct Booking {
  std::int64_t id = 0;
  std::int64_t station_id = 0;
  std::string station_name;
  std::int64_t user_id = 0;
  std::string username;
  std::int64_t starts_at = 0;  // Unix seconds, inclusive
  std::int64_t ends_at = 0;    // Unix seconds, exclusive
  // "active", "cancelled", or "completed": the session held in it ended, and ends_at was cut
  // back to that moment (complete_for_session).
  std::string status;
  std::int64_t created_at = 0;
};

// Whether the booking holds its station at `now`: active (not cancelled, not completed) and
// starts_at <= now < ends_at. BookingsRepo::covering asks the same of the table.
inline bool covers(const Booking& booking, std::int64_t now) {
  return booking.status == "active" && booking.starts_at <= now && now < booking.ends_at;
}

// The slot overlaps `existing`, at the same station or of the same person.
class BookingConflict : public Conflict {
 public:
  BookingConflict(Booking existing, bool same_station)
      : Conflict("booking overlaps an existing booking"),
        existing_(std::move(existing)),
        same_station_(same_station) {}
  const Booking& existing() const { return existing_; }
  bool same_station() const { return same_station_; }

 private:
  Booking existing_;
  bool same_station_;
};

class BookingsRepo {
 public:
  explicit BookingsRepo(Database& db) : db_(db) {}

  // Throws NotFound for an unknown station or user, BookingConflict on overlap, and
  // std::invalid_argument for an empty or reversed interval.
  Booking create(std::int64_t station_id, std::int64_t user_id, std::int64_t starts_at,
                 std::int64_t ends_at, std::int64_t now);
  std::optional<Booking> find(std::int64_t id);
  // Newest first by start time; `user_id` restricts to one person's bookings.
  std::vector<Booking> list(std::optional<std::int64_t> user_id = std::nullopt) {
    return list(user_id ? TraineeScope::of_trainee(*user_id) : TraineeScope::everyone());
  }
  // Newest first by start, of the people in scope (a booking's user as the trainee).
  std::vector<Booking> list(const TraineeScope& scope);
  // The active bookings of a station that end after #since, earliest first: its calendar.
  std::vector<Booking> station_schedule(std::int64_t station_id, std::int64_t since);
  // Throws NotFound for an unknown id, Conflict when already cancelled or completed.
  void cancel(std::int64_t id, std::int64_t now);
  // The person's booking of the station that covers `now` (covers() above).
  std::optional<Booking> covering(std::int64_t user_id, std::int64_t station_id, std::int64_t now);
  // Bookings follow sessions: when the session started in a booking (sessions.booking_id) ends,
  // the booking is completed and ends at #now (never later than it did, and after its start), so
  // the rest of the slot is free and the person may book another station at once. False when the
  // session has no booking or it is no longer active.
  bool complete_for_session(std::int64_t session_id, std::int64_t now);

 private:
  Database& db_;
};

}  // namespace incise::db
