// Properties of db/bookings_repo.h over many operations: after any sequence of creates and
// cancels no two active bookings of one station or of one person overlap, and every refusal
// names a real overlap. Then the same under two connections racing for the same slots.
#include <gtest/gtest.h>

#include <atomic>
#include <barrier>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "db/bookings_repo.h"
#include "db/statement.h"
#include "temp_database.h"

namespace incise::db {
namespace {

struct Row {
  std::int64_t id, station, user, t0, t1;
};

// "s" + std::to_string(i) trips a GCC 12 false -Wrestrict warning; appending does not.
std::string numbered(const char* prefix, int i) {
  std::string name = prefix;
  name += std::to_string(i);
  return name;
}

bool overlap(const Row& a, std::int64_t t0, std::int64_t t1) {
  return a.t0 < t1 && t0 < a.t1;
}

// Read with plain SQL, independently of the repository under test.
std::vector<Row> active_bookings(Database& db) {
  auto q = db.prepare(
      "SELECT id, station_id, user_id, starts_at, ends_at FROM bookings WHERE status = 'active'");
  std::vector<Row> rows;
  while (q.step())
    rows.push_back({q.int64(0), q.int64(1), q.int64(2), q.int64(3), q.int64(4)});
  return rows;
}

void expect_no_overlaps(Database& db) {
  const auto rows = active_bookings(db);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (std::size_t j = i + 1; j < rows.size(); ++j) {
      const Row& a = rows[i];
      const Row& b = rows[j];
      if (a.station != b.station && a.user != b.user) continue;
      EXPECT_FALSE(overlap(a, b.t0, b.t1)) << "bookings " << a.id << " and " << b.id;
    }
  }
}

TEST(BookingsProperty, RandomCreatesAndCancelsKeepBookingsDisjoint) {
  test::TempDatabase tmp;
  Database& db = tmp.db();
  std::vector<std::int64_t> stations, users;
  for (int i = 0; i < 3; ++i)
    stations.push_back(test::add_station(db, numbered("s", i)));
  for (int i = 0; i < 4; ++i)
    users.push_back(test::add_user(db, numbered("u", i)));
  BookingsRepo repo(db);

  std::mt19937 rng(20240611);
  auto pick = [&](const std::vector<std::int64_t>& v) { return v[rng() % v.size()]; };
  int created = 0, refused = 0, cancelled = 0;
  for (int op = 0; op < 500; ++op) {
    const auto before = active_bookings(db);
    if (!before.empty() && rng() % 4 == 0) {
      repo.cancel(before[rng() % before.size()].id, op);
      ++cancelled;
      continue;
    }
    const std::int64_t station = pick(stations), user = pick(users);
    const std::int64_t t0 = rng() % 200, t1 = t0 + 1 + rng() % 12;
    bool station_busy = false, user_busy = false;
    for (const Row& r : before) {
      station_busy |= r.station == station && overlap(r, t0, t1);
      user_busy |= r.user == user && overlap(r, t0, t1);
    }
    try {
      const Booking b = repo.create(station, user, t0, t1, op);
      ++created;
      EXPECT_FALSE(station_busy || user_busy) << "op " << op << ": accepted an overlap";
      EXPECT_EQ(b.station_id, station);
      EXPECT_EQ(b.user_id, user);
      EXPECT_EQ(b.starts_at, t0);
      EXPECT_EQ(b.ends_at, t1);
    } catch (const BookingConflict& e) {
      ++refused;
      ASSERT_TRUE(station_busy || user_busy) << "op " << op << ": refused without an overlap";
      const Booking& other = e.existing();
      bool named_is_real = false;
      for (const Row& r : before) {
        named_is_real |= r.id == other.id && overlap(r, t0, t1) &&
                         (e.same_station() ? r.station == station : r.user == user);
      }
      EXPECT_TRUE(named_is_real) << "op " << op << ": existing() is not an overlapping booking";
      EXPECT_EQ(active_bookings(db).size(), before.size()) << "op " << op;
    }
  }
  // The sequence exercised every path.
  EXPECT_GT(created, 50);
  EXPECT_GT(refused, 50);
  EXPECT_GT(cancelled, 50);
  expect_no_overlaps(db);
}

// Two connections, each in its own thread, try to book the same slots; per slot exactly one may
// win. `station_of` and `user_of` choose who books what in thread t.
template <class StationOf, class UserOf>
void race_for_slots(StationOf station_of, UserOf user_of) {
  test::TempDatabase tmp;
  const std::int64_t stations[] = {test::add_station(tmp.db(), "s0"),
                                   test::add_station(tmp.db(), "s1")};
  const std::int64_t users[] = {test::add_user(tmp.db(), "u0"), test::add_user(tmp.db(), "u1")};
  constexpr int kSlots = 150;
  std::unique_ptr<Database> connections[] = {tmp.open_another(), tmp.open_another()};
  std::vector<int> wins[2];
  std::atomic<int> unexpected{0};
  std::barrier in_step(2);  // both threads start each slot together, so they really race
  auto book = [&](int t) {
    BookingsRepo repo(*connections[t]);
    for (int slot = 0; slot < kSlots; ++slot) {
      in_step.arrive_and_wait();
      try {
        repo.create(stations[station_of(t)], users[user_of(t)], slot * 10, slot * 10 + 10, t);
        wins[t].push_back(slot);
      } catch (const BookingConflict&) {
      } catch (...) {
        ++unexpected;
      }
    }
  };
  std::thread a(book, 0), b(book, 1);
  a.join();
  b.join();

  EXPECT_EQ(unexpected.load(), 0) << "a create failed with something other than a conflict";
  EXPECT_EQ(wins[0].size() + wins[1].size(), static_cast<std::size_t>(kSlots));
  std::vector<int> winners(kSlots, 0);
  for (const auto& w : wins)
    for (const int slot : w)
      ++winners[slot];
  for (int slot = 0; slot < kSlots; ++slot)
    EXPECT_EQ(winners[slot], 1) << "slot " << slot;
  EXPECT_EQ(test::row_count(tmp.db(), "bookings"), kSlots);
  expect_no_overlaps(tmp.db());
}

TEST(BookingsProperty, TwoConnectionsRacingForOneStationBookEachSlotOnce) {
  race_for_slots([](int) { return 0; }, [](int t) { return t; });
}

TEST(BookingsProperty, TwoConnectionsRacingForOnePersonBookEachSlotOnce) {
  race_for_slots([](int t) { return t; }, [](int) { return 0; });
}

}  // namespace
}  // namespace incise::db
