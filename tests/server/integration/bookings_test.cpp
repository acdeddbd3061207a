// Booking a station slot on the real server: the whole flow, and a race for one slot.
#include <gtest/gtest.h>

#include <latch>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "server_fixture.h"

namespace incise::server::test {
namespace {

using Bookings = ServerTest;

nlohmann::json slot(std::int64_t station, std::int64_t starts, std::int64_t ends) {
  return {{"station_id", station}, {"starts_at", utc_text(starts)}, {"ends_at", utc_text(ends)}};
}

std::int64_t station_1(HttpClient& client) {
  const auto stations = client.get("/api/stations").json();
  for (const auto& s : stations) {
    if (s["name"] == "Station 1") return s["id"].get<std::int64_t>();
  }
  ADD_FAILURE() << "no Station 1 in " << stations;
  return 0;
}

TEST_F(Bookings, BookConflictCancelRebook) {
  auto& trainee = as(kTrainee);
  auto& admin = as(kAdmin);
  const auto station = station_1(trainee);
  const auto start = quarter_hour_in_days(3);
  const auto end = start + 3600;

  const auto booked = trainee.post("/api/bookings", slot(station, start, end));
  ASSERT_EQ(booked.status, 201) << booked.error();
  const auto b = booked.json();
  EXPECT_EQ(b.size(), 9u) << b;
  EXPECT_TRUE(b["id"].is_number_integer());
  EXPECT_EQ(b["station_id"], station);
  EXPECT_EQ(b["station_name"], "Station 1");
  EXPECT_EQ(b["user_id"], trainee.get("/api/me").json()["id"]);
  EXPECT_EQ(b["username"], "trainee");
  EXPECT_EQ(b["starts_at"], utc_text(start));
  EXPECT_EQ(b["ends_at"], utc_text(end));
  EXPECT_EQ(b["status"], "active");
  EXPECT_TRUE(b["created_at"].is_string());
  const auto path = "/api/bookings/" + b["id"].dump();
  const std::string span = " from " + utc_text(start) + " to " + utc_text(end);

  auto before = snapshot();
  EXPECT_TRUE(is_error(trainee.post("/api/bookings", slot(station, start, end)), 409,
                       "Station 1 is already booked" + span));
  EXPECT_TRUE(
      is_error(as(kInstructor).post("/api/bookings", slot(station, start + 1800, end + 1800)), 409,
               "Station 1 is already booked" + span));
  EXPECT_EQ(snapshot(), before);

  const auto created = admin.post("/api/stations", {{"name", "Station 2"}, {"location", "room 3"}});
  ASSERT_EQ(created.status, 201) << created.error();
  const auto station_2 = created.json()["station"]["id"].get<std::int64_t>();
  before = snapshot();
  EXPECT_TRUE(is_error(trainee.post("/api/bookings", slot(station_2, start - 900, start + 900)),
                       409, "you already have a booking at Station 1" + span));
  EXPECT_EQ(snapshot(), before);

  EXPECT_EQ(trainee.del(path).status, 204);
  before = snapshot();
  EXPECT_TRUE(
      is_error(trainee.del(path), 409, "booking " + b["id"].dump() + " is already cancelled"));
  EXPECT_EQ(snapshot(), before);

  const auto rebooked = trainee.post("/api/bookings", slot(station, start, end));
  ASSERT_EQ(rebooked.status, 201) << rebooked.error();
  EXPECT_NE(rebooked.json()["id"], b["id"]);
  const auto mine = trainee.get("/api/bookings").json();
  ASSERT_EQ(mine.size(), 2u) << mine;
  EXPECT_EQ(mine[0]["status"].get<std::string>() + mine[1]["status"].get<std::string>(),
            rebooked.json()["id"] > b["id"] ? "activecancelled" : "cancelledactive");
}

TEST_F(Bookings, OnlyOneOfEightRacersGetsTheSlot) {
  constexpr int kRacers = 8;
  auto& admin = as(kAdmin);
  const auto station = station_1(admin);
  std::vector<std::unique_ptr<HttpClient>> clients;
  for (int i = 0; i < kRacers; ++i) {
    const std::string name = "racer-" + std::to_string(i);
    const auto created = admin.post(
        "/api/users", {{"username", name}, {"password", "racing-password"}, {"role", "trainee"}});
    ASSERT_EQ(created.status, 201) << created.error();
    clients.push_back(new_client());
    ASSERT_EQ(clients.back()->login(name, "racing-password").status, 200);
    clients.back()->connect();
  }
  const auto start = quarter_hour_in_days(5);
  const auto body = slot(station, start, start + 1800);
  std::vector<HttpResponse> responses(kRacers);
  std::latch go(kRacers);
  std::vector<std::thread> threads;
  for (int i = 0; i < kRacers; ++i) {
    threads.emplace_back([&, i] {
      go.arrive_and_wait();
      responses[i] = clients[i]->post("/api/bookings", body);
    });
  }
  for (auto& t : threads)
    t.join();

  int created = 0;
  for (const auto& r : responses) {
    if (r.status == 201) {
      ++created;
    } else {
      EXPECT_TRUE(is_error(
          r, 409,
          "Station 1 is already booked from " + utc_text(start) + " to " + utc_text(start + 1800)));
    }
  }
  EXPECT_EQ(created, 1);
  EXPECT_EQ(db_int("SELECT COUNT(*) FROM bookings WHERE status = 'active' AND station_id = " +
                   std::to_string(station) + " AND starts_at = " + std::to_string(start)),
            1);
}

}  // namespace
}  // namespace incise::server::test
