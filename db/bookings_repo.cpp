#include "db/bookings_repo.h"

#include <stdexcept>

#include "db/statement.h"
#include "db/transaction.h"

namespace incise::db {

namespace {
constexpr const char* kSelect =
    "SELECT b.id, b.station_id, s.name, b.user_id, u.username, b.starts_at, b.ends_at, "
    "CASE WHEN b.completed_at IS NOT NULL THEN 'completed' ELSE b.status END, b.created_at FROM "
    "bookings b JOIN stations s ON s.id = b.station_id JOIN users u ON u.id = "
    "b.user_id ";

Booking read_booking(const Statement& q) {
  return Booking{q.int64(0), q.int64(1), q.text(2), q.int64(3), q.text(4),
                 q.int64(5), q.int64(6), q.text(7), q.int64(8)};
}

// Half-open intervals [a0, a1) and [b0, b1) overlap when a0 < b1 and b0 < a1.
std::optional<Booking> first_overlap(Database& db, const char* owner_column, std::int64_t owner,
                                     std::int64_t starts_at, std::int64_t ends_at) {
  // A completed booking ended when its session did, at a moment now past: the time it held is
  // spent, so a walk-up slot that began before that moment may still be booked.
  auto q = db.prepare(std::string(kSelect) +
                      "WHERE b.status = 'active' AND b.completed_at IS NULL AND b." + owner_column +
                      " = ? AND b.starts_at < ? AND ? < b.ends_at ORDER BY b.starts_at LIMIT 1");
  q.bind(1, owner).bind(2, ends_at).bind(3, starts_at);
  if (!q.step()) return std::nullopt;
  return read_booking(q);
}
}  // namespace

Booking BookingsRepo::create(std::int64_t station_id, std::int64_t user_id, std::int64_t starts_at,
                             std::int64_t ends_at, std::int64_t now) {
  if (ends_at <= starts_at) {
    throw std::invalid_argument("a booking must end after it starts");
  }
  Transaction tx(db_);
  {
    auto q = db_.prepare("SELECT 1 FROM users WHERE id = ?");
    q.bind(1, user_id);
    if (!q.step()) throw NotFound("user " + std::to_string(user_id) + " does not exist");
  }
  {
    auto q = db_.prepare("SELECT 1 FROM stations WHERE id = ?");
    q.bind(1, station_id);
    if (!q.step()) throw NotFound("station " + std::to_string(station_id) + " does not exist");
  }
  if (auto other = first_overlap(db_, "station_id", station_id, starts_at, ends_at)) {
    throw BookingConflict(*other, true);
  }
  if (auto other = first_overlap(db_, "user_id", user_id, starts_at, ends_at)) {
    throw BookingConflict(*other, false);
  }
  std::int64_t id = 0;
  try {
    id = db_.prepare(
                "INSERT INTO bookings (station_id, user_id, starts_at, ends_at, created_at) VALUES "
                "(?, ?, ?, ?, ?) RETURNING id")
             .bind(1, station_id)
             .bind(2, user_id)
             .bind(3, starts_at)
             .bind(4, ends_at)
             .bind(5, now)
             .insert();
  } catch (const ConstraintError&) {
    throw NotFound("user " + std::to_string(user_id) + " does not exist");
  }
  tx.commit();
  return *find(id);
}

std::optional<Booking> BookingsRepo::find(std::int64_t id) {
  auto q = db_.prepare(std::string(kSelect) + "WHERE b.id = ?");
  q.bind(1, id);
  if (!q.step()) return std::nullopt;
  return read_booking(q);
}

std::vector<Booking> BookingsRepo::list(const TraineeScope& scope) {
  auto q = db_.prepare(std::string(kSelect) + scope.where("b.user_id") +
                       "ORDER BY b.starts_at DESC, b.id DESC");
  if (scope.binds()) q.bind(1, scope.user_id);
  std::vector<Booking> out;
  while (q.step())
    out.push_back(read_booking(q));
  return out;
}

std::vector<Booking> BookingsRepo::station_schedule(std::int64_t station_id, std::int64_t since) {
  auto q = db_.prepare(std::string(kSelect) +
                       "WHERE b.station_id = ? AND b.status = 'active' AND b.ends_at > ? "
                       "ORDER BY b.starts_at, b.id");
  q.bind(1, station_id);
  q.bind(2, since);
  std::vector<Booking> out;
  while (q.step())
    out.push_back(read_booking(q));
  return out;
}

void BookingsRepo::cancel(std::int64_t id, std::int64_t now) {
  Transaction tx(db_);
  auto booking = find(id);
  if (!booking) throw NotFound("booking " + std::to_string(id) + " does not exist");
  if (booking->status != "active") {
    throw Conflict("booking " + std::to_string(id) + " is already " + booking->status);
  }
  db_.prepare("UPDATE bookings SET status = 'cancelled', cancelled_at = ? WHERE id = ?")
      .bind(1, now)
      .bind(2, id)
      .run();
  tx.commit();
}

std::optional<Booking> BookingsRepo::covering(std::int64_t user_id, std::int64_t station_id,
                                              std::int64_t now) {
  auto q = db_.prepare(std::string(kSelect) +
                       "WHERE b.status = 'active' AND b.completed_at IS NULL AND b.user_id = ? AND "
                       "b.station_id = ? AND b.starts_at <= ? AND ? < b.ends_at LIMIT 1");
  q.bind(1, user_id).bind(2, station_id).bind(3, now).bind(4, now);
  if (!q.step()) return std::nullopt;
  return read_booking(q);
}

bool BookingsRepo::complete_for_session(std::int64_t session_id, std::int64_t now) {
  // ends_at stays after starts_at (the table's CHECK) and never moves later.
  db_.prepare(
         "UPDATE bookings SET ends_at = CASE WHEN ?1 < starts_at + 1 THEN starts_at + 1 WHEN ?1 < "
         "ends_at THEN ?1 ELSE ends_at END, completed_at = ?1 "
         "WHERE id = (SELECT booking_id FROM sessions WHERE id = ?2) AND status = 'active' AND "
         "completed_at IS NULL")
      .bind(1, now)
      .bind(2, session_id)
      .run();
  return db_.changes() > 0;
}

}  // namespace incise::db
