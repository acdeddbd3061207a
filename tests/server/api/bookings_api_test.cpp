// Booking endpoints: server/api/bookings_api.cpp through the router.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "api_test_app.h"
#include "db/bookings_repo.h"
#include "db/stations_repo.h"
#include "server/time_text.h"

namespace incise::server::test {
namespace {

constexpr std::int64_t kHour = 3600;

class BookingsApi : public ApiTest {
 protected:
  void SetUp() override {
    ApiTest::SetUp();
    trainee_ = session_of(Who::trainee);
    instructor_ = session_of(Who::instructor);
    admin_ = session_of(Who::admin);
    station_ = demo_station_id();
  }

  static nlohmann::json slot(std::int64_t station, std::int64_t starts, std::int64_t ends) {
    return {
        {"station_id", station}, {"starts_at", format_utc(starts)}, {"ends_at", format_utc(ends)}};
  }

  Response book(std::int64_t starts, std::int64_t ends, const std::string& token) {
    return post("/api/bookings", slot(station_, starts, ends), token);
  }

  std::int64_t second_station() {
    return db::StationsRepo(db()).create("Station 2", "", "second-token", now()).id;
  }

  std::string trainee_, instructor_, admin_;
  std::int64_t station_ = 0;
  const std::int64_t t_ = kStart + kDay;  // a bookable quarter hour
};

TEST_F(BookingsApi, CreateReturnsTheBooking) {
  const auto response = book(t_, t_ + kHour, trainee_);
  ASSERT_EQ(response.result(), http::status::created) << response.body();
  const auto b = json_of(response);
  const std::set<std::string> keys = {"id",      "station_id", "station_name",
                                      "user_id", "username",   "starts_at",
                                      "ends_at", "status",     "created_at"};
  std::set<std::string> got;
  for (const auto& [key, _] : b.items())
    got.insert(key);
  EXPECT_EQ(got, keys);
  EXPECT_TRUE(b["id"].is_number_integer());
  EXPECT_EQ(b["station_id"], station_);
  EXPECT_EQ(b["station_name"], "Station 1");
  EXPECT_EQ(b["user_id"], user_id("trainee"));
  EXPECT_EQ(b["username"], "trainee");
  EXPECT_EQ(b["starts_at"], "2030-01-08T08:00:00Z");
  EXPECT_EQ(b["ends_at"], "2030-01-08T09:00:00Z");
  EXPECT_EQ(b["status"], "active");
  EXPECT_EQ(b["created_at"], "2030-01-07T08:00:00Z");
}

// The list says which booking lets its person start now, by the server's clock and rule.
TEST_F(BookingsApi, TheListSaysWhichBookingCoversNow) {
  ASSERT_EQ(book(t_, t_ + kHour, trainee_).result(), http::status::created);
  const auto covers_now = [&] {
    // A fresh login each time: the clock moves past the first one's lifetime.
    return json_of(get("/api/bookings", session_of(Who::trainee)))[0]["covers_now"].get<bool>();
  };
  EXPECT_FALSE(covers_now());  // it starts tomorrow
  set_now(t_);
  EXPECT_TRUE(covers_now());  // its first second
  set_now(t_ + kHour - 1);
  EXPECT_TRUE(covers_now());
  set_now(t_ + kHour);
  EXPECT_FALSE(covers_now());  // the end is not in it
  set_now(t_ + 60);
  const auto id =
      json_of(get("/api/bookings", session_of(Who::trainee)))[0]["id"].get<std::int64_t>();
  db::BookingsRepo(db()).cancel(id, now());
  EXPECT_FALSE(covers_now());  // cancelled
}

TEST_F(BookingsApi, JavaScriptTimesAreAccepted) {
  const nlohmann::json body = {{"station_id", station_},
                               {"starts_at", "2030-01-08T08:00:00.000Z"},
                               {"ends_at", "2030-01-08T08:15:00.000Z"}};
  EXPECT_EQ(post("/api/bookings", body, trainee_).result(), http::status::created);
}

TEST_F(BookingsApi, InvalidSlotsAre422) {
  const auto bookings = count("bookings");
  EXPECT_TRUE(is_error(book(t_, t_, trainee_), http::status::unprocessable_entity,
                       "ends_at must be after starts_at"));
  EXPECT_TRUE(is_error(book(t_ + 60, t_ + kHour, trainee_), http::status::unprocessable_entity,
                       "slots start and end on whole quarter hours"));
  EXPECT_TRUE(is_error(book(t_, t_ + 5 * kHour, trainee_), http::status::unprocessable_entity,
                       "a slot lasts from 15 minutes to 4 hours"));
  EXPECT_TRUE(is_error(book(kStart - kHour, kStart, trainee_), http::status::unprocessable_entity,
                       "starts_at is in the past"));
  EXPECT_TRUE(is_error(book(kStart + 181 * kDay, kStart + 181 * kDay + kHour, trainee_),
                       http::status::unprocessable_entity, "bookings open at most 180 days ahead"));
  EXPECT_TRUE(is_error(post("/api/bookings", slot(9999, t_, t_ + kHour), trainee_),
                       http::status::unprocessable_entity, "station 9999 does not exist"));

  auto body = slot(station_, t_, t_ + kHour);
  body["starts_at"] = "2030-01-08 08:00";
  EXPECT_TRUE(is_error(post("/api/bookings", body, trainee_), http::status::unprocessable_entity,
                       "field 'starts_at' must be a UTC time like 2026-11-21T14:00:00Z (got "
                       "'2030-01-08 08:00')"));
  body = slot(station_, t_, t_ + kHour);
  body["station_id"] = "1";
  EXPECT_TRUE(is_error(post("/api/bookings", body, trainee_), http::status::unprocessable_entity,
                       "field 'station_id' must be an integer"));
  body = slot(station_, t_, t_ + kHour);
  body["user_id"] = user_id("admin");  // one cannot book for somebody else
  EXPECT_TRUE(is_error(post("/api/bookings", body, trainee_), http::status::unprocessable_entity,
                       "unknown field 'user_id'"));
  body = slot(station_, t_, t_ + kHour);
  body.erase("ends_at");
  EXPECT_TRUE(is_error(post("/api/bookings", body, trainee_), http::status::unprocessable_entity,
                       "missing field 'ends_at'"));
  EXPECT_EQ(count("bookings"), bookings);
}

TEST_F(BookingsApi, OverlapsAre409NamingTheConflict) {
  ASSERT_EQ(book(t_, t_ + 2 * kHour, trainee_).result(), http::status::created);
  const auto bookings = count("bookings");
  // Same station, another person, overlapping at either end or inside.
  for (const auto& [s, e] :
       {std::pair{t_, t_ + 2 * kHour}, std::pair{t_ - kHour, t_ + 900},
        std::pair{t_ + kHour + 2700, t_ + 3 * kHour}, std::pair{t_ + 900, t_ + 1800}}) {
    EXPECT_TRUE(is_error(book(s, e, instructor_), http::status::conflict,
                         "Station 1 is already booked from 2030-01-08T08:00:00Z to "
                         "2030-01-08T10:00:00Z"));
  }
  // The same person at another station.
  const auto other = second_station();
  EXPECT_TRUE(is_error(post("/api/bookings", slot(other, t_ + kHour, t_ + 3 * kHour), trainee_),
                       http::status::conflict,
                       "you already have a booking at Station 1 from 2030-01-08T08:00:00Z to "
                       "2030-01-08T10:00:00Z"));
  EXPECT_EQ(count("bookings"), bookings);
  // Touching slots do not overlap: [8, 10) and [10, 11).
  EXPECT_EQ(book(t_ + 2 * kHour, t_ + 3 * kHour, instructor_).result(), http::status::created);
  EXPECT_EQ(book(t_ - kHour, t_, admin_).result(), http::status::created);
  EXPECT_TRUE(is_error(post("/api/bookings", slot(other, t_ - 1800, t_ + 900), admin_),
                       http::status::conflict,
                       "you already have a booking at Station 1 from 2030-01-08T07:00:00Z to "
                       "2030-01-08T08:00:00Z"));
  EXPECT_EQ(post("/api/bookings", slot(other, t_, t_ + kHour), instructor_).result(),
            http::status::created);
}

TEST_F(BookingsApi, TraineesSeeOnlyTheirOwnBookings) {
  const auto other = add_trainee("trainee2");
  db::BookingsRepo(db()).create(station_, other, t_, t_ + kHour, now());
  ASSERT_EQ(book(t_ + kHour, t_ + 2 * kHour, trainee_).result(), http::status::created);
  ASSERT_EQ(book(t_ + 2 * kHour, t_ + 3 * kHour, instructor_).result(), http::status::created);

  const auto mine = json_of(get("/api/bookings", trainee_));
  ASSERT_EQ(mine.size(), 1u) << mine;
  EXPECT_EQ(mine[0]["username"], "trainee");
  for (const auto& token : {instructor_, admin_}) {
    const auto all = json_of(get("/api/bookings", token));
    ASSERT_EQ(all.size(), 3u) << all;
    // Newest first by start time.
    EXPECT_EQ(all[0]["username"], "instructor");
    EXPECT_EQ(all[1]["username"], "trainee");
    EXPECT_EQ(all[2]["username"], "trainee2");
  }
}

// The calendar's view of a station: a trainee sees every active booking as a taken slot, but
// the id and name only of their own; staff see whose each is. Cancelled ones and other stations'
// are left out, and so is what ended more than a week ago.
TEST_F(BookingsApi, AStationsScheduleShowsTakenSlotsWithoutNamingOthersToTrainees) {
  const auto other = add_trainee("trainee2");
  db::BookingsRepo bookings(db());
  const auto theirs = bookings.create(station_, other, t_, t_ + kHour, now());
  ASSERT_EQ(book(t_ + kHour, t_ + 2 * kHour, trainee_).result(), http::status::created);
  const auto cancelled = bookings.create(station_, other, t_ + 3 * kHour, t_ + 4 * kHour, now());
  bookings.cancel(cancelled.id, now());
  bookings.create(second_station(), other, t_ + 5 * kHour, t_ + 6 * kHour, now());
  const auto path = "/api/stations/" + std::to_string(station_) + "/schedule";

  const auto seen = json_of(get(path, trainee_));
  ASSERT_EQ(seen.size(), 2u) << seen;
  EXPECT_EQ(seen[0], (nlohmann::json{{"id", nullptr},
                                     {"starts_at", format_utc(t_)},
                                     {"ends_at", format_utc(t_ + kHour)},
                                     {"mine", false},
                                     {"username", nullptr}}));
  EXPECT_TRUE(seen[1]["mine"].get<bool>());
  EXPECT_TRUE(seen[1]["id"].is_number_integer());
  EXPECT_TRUE(seen[1]["username"].is_null());
  const auto staff = json_of(get(path, instructor_));
  ASSERT_EQ(staff.size(), 2u);
  EXPECT_EQ(staff[0]["id"], theirs.id);
  EXPECT_EQ(staff[0]["username"], "trainee2");  // the demo instructor teaches trainee2
  // A trainee the instructor does not teach stays unnamed to them, not to an admin.
  const auto untaught = add_trainee("trainee3", false);
  bookings.create(station_, untaught, t_ + 6 * kHour, t_ + 7 * kHour, now());
  const auto by_instructor = json_of(get(path, instructor_));
  ASSERT_EQ(by_instructor.size(), 3u);
  EXPECT_TRUE(by_instructor[2]["id"].is_null());
  EXPECT_TRUE(by_instructor[2]["username"].is_null());
  EXPECT_EQ(json_of(get(path, admin_))[2]["username"], "trainee3");

  // Eight days on, both have ended more than a week ago.
  set_now(t_ + 2 * kHour + 8 * kDay);
  EXPECT_TRUE(json_of(get(path, session_of(Who::trainee))).empty());
  EXPECT_TRUE(
      is_error(get("/api/stations/999/schedule", session_of(Who::admin)), http::status::not_found));
}

TEST_F(BookingsApi, OnlyTheOwnerOrAnAdminCancels) {
  const auto other = add_trainee("trainee2");
  const auto foreign = db::BookingsRepo(db()).create(station_, other, t_, t_ + kHour, now()).id;
  const auto path = "/api/bookings/" + std::to_string(foreign);
  EXPECT_TRUE(is_error(del(path, trainee_), http::status::forbidden,
                       "you can cancel only your own bookings"));
  EXPECT_TRUE(is_error(del(path, instructor_), http::status::forbidden,
                       "you can cancel only your own bookings"));
  EXPECT_EQ(db::BookingsRepo(db()).find(foreign)->status, "active");
  const auto audits = count("audit_log");
  EXPECT_EQ(del(path, admin_).result(), http::status::no_content);
  EXPECT_EQ(db::BookingsRepo(db()).find(foreign)->status, "cancelled");
  EXPECT_EQ(count("audit_log"), audits + 1);  // an admin's cancellation of another's is audited
  EXPECT_TRUE(is_error(del(path, admin_), http::status::conflict,
                       "booking " + std::to_string(foreign) + " is already cancelled"));
  // Cancelled bookings stay listed.
  const auto all = json_of(get("/api/bookings", admin_));
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0]["status"], "cancelled");
}

TEST_F(BookingsApi, CancelFreesTheSlot) {
  const auto response = book(t_, t_ + kHour, trainee_);
  ASSERT_EQ(response.result(), http::status::created);
  const auto path = "/api/bookings/" + json_of(response)["id"].dump();
  EXPECT_EQ(book(t_, t_ + kHour, instructor_).result(), http::status::conflict);
  EXPECT_EQ(del(path, trainee_).result(), http::status::no_content);
  EXPECT_TRUE(is_error(del(path, trainee_), http::status::conflict));
  EXPECT_EQ(book(t_, t_ + kHour, instructor_).result(), http::status::created);
  EXPECT_TRUE(is_error(del("/api/bookings/424242", admin_), http::status::not_found,
                       "booking 424242 does not exist"));
}

}  // namespace
}  // namespace incise::server::test
