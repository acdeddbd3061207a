#include "db/stations_repo.h"
#include "db/transaction.h"
#include "server/api/api_error.h"
#include "server/api/audit_change.h"
#include "server/api/handlers.h"
#include "server/api/json_views.h"
#include "server/api/live_access.h"
#include "server/api/request_fields.h"
#include "server/booking_rules.h"
#include "server/time_text.h"

namespace incise::server::api {

namespace {
std::int64_t time_field(const RequestFields& fields, std::string_view key) {
  const auto text = fields.string(key);
  const auto t = parse_utc(text);
  if (!t) {
    throw ApiError(http::status::unprocessable_entity,
                   "field '" + std::string(key) +
                       "' must be a UTC time like 2026-11-21T14:00:00Z (got '" + text + "')");
  }
  return *t;
}

std::string conflict_message(const db::BookingConflict& c) {
  const auto& other = c.existing();
  const auto span = " from " + format_utc(other.starts_at) + " to " + format_utc(other.ends_at);
  if (c.same_station()) return other.station_name + " is already booked" + span;
  return "you already have a booking at " + other.station_name + span;
}
}  // namespace

ApiResponse list_bookings(ApiContext& ctx) {
  const auto& user = ctx.user();
  auto out = nlohmann::json::array();
  for (const auto& b : db::BookingsRepo(ctx.db()).list(visible_scope(user))) {
    auto row = to_json(b);
    // Whether it lets its person start a session now: the browser shows the start form by it.
    row["covers_now"] = db::covers(b, ctx.now);
    out.push_back(std::move(row));
  }
  return {http::status::ok, out, {}};
}

ApiResponse station_schedule(ApiContext& ctx) {
  const auto& user = ctx.user();
  auto& db = ctx.db();
  if (!db::StationsRepo(db).find(ctx.path_id)) {
    throw ApiError(http::status::not_found,
                   "station " + std::to_string(ctx.path_id) + " does not exist");
  }
  // From a week back, so that the calendar's current week shows its past slots too. Everyone
  // sees that a slot is taken; whose it is only those who may see that person's records (their
  // own, an instructor's trainees, an admin everyone's): others' ids and names stay hidden.
  constexpr std::int64_t kWeek = 7 * 24 * 3600;
  auto out = nlohmann::json::array();
  for (const auto& b : db::BookingsRepo(db).station_schedule(ctx.path_id, ctx.now - kWeek)) {
    const bool mine = b.user_id == user.id;
    const bool named = may_see_trainee(db, user, b.user_id);
    out.push_back(
        {{"id", named ? nlohmann::json(b.id) : nlohmann::json(nullptr)},
         {"starts_at", format_utc(b.starts_at)},
         {"ends_at", format_utc(b.ends_at)},
         {"mine", mine},
         {"username", named && !mine ? nlohmann::json(b.username) : nlohmann::json(nullptr)}});
  }
  return {http::status::ok, std::move(out), {}};
}

ApiResponse create_booking(ApiContext& ctx) {
  const auto& user = ctx.user();
  const auto body = ctx.json_body();
  const RequestFields fields(body, {"station_id", "starts_at", "ends_at"});
  const auto station_id = fields.integer("station_id");
  const auto starts_at = time_field(fields, "starts_at");
  const auto ends_at = time_field(fields, "ends_at");
  if (const auto why = check_slot(starts_at, ends_at, ctx.now)) {
    throw ApiError(http::status::unprocessable_entity, *why);
  }
  // The retired check holds for the insert: a station retired meanwhile is not booked.
  db::Transaction tx(ctx.db());
  if (const auto station = db::StationsRepo(ctx.db()).find(station_id);
      station && station->retired()) {
    throw ApiError(http::status::conflict, station->name + " is retired; book another station");
  }
  try {
    const auto booking =
        db::BookingsRepo(ctx.db()).create(station_id, user.id, starts_at, ends_at, ctx.now);
    tx.commit();
    return {http::status::created, to_json(booking), {}};
  } catch (const db::BookingConflict& c) {
    throw ApiError(http::status::conflict, conflict_message(c));
  } catch (const db::NotFound& e) {
    // The station named in the body does not exist: the body is wrong, not the URL.
    throw ApiError(http::status::unprocessable_entity, e.what());
  }
}

ApiResponse cancel_booking(ApiContext& ctx) {
  const auto& user = ctx.user();
  db::BookingsRepo bookings(ctx.db());
  db::Transaction tx(ctx.db());  // the cancellation and its audit entry, both or neither
  const auto booking = bookings.find(ctx.path_id);
  if (!booking) {
    throw ApiError(http::status::not_found,
                   "booking " + std::to_string(ctx.path_id) + " does not exist");
  }
  if (booking->user_id != user.id && user.role != db::Role::admin) {
    // A trainee must not learn whose booking it is: same answer for every foreign booking.
    throw ApiError(http::status::forbidden, "you can cancel only your own bookings");
  }
  bookings.cancel(booking->id, ctx.now);
  if (booking->user_id != user.id) {
    audit_change(ctx.db(), user.id, "booking.cancel",
                 "booking " + std::to_string(booking->id) + " of " + booking->username, ctx.now,
                 {{"status", booking->status}}, {{"status", "cancelled"}});
  }
  tx.commit();
  return {http::status::no_content, nullptr, {}};
}

}  // namespace incise::server::api
