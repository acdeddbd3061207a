// Tests for db/connection_pool.h on the suite's engine: at most max connections, waiters served
// as leases come back, a connection never handed on inside a transaction, and a failed open gives
// its slot back.
#include "db/connection_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <future>
#include <thread>
#include <vector>

#include "db/statement.h"
#include "temp_database.h"

namespace incise::db {
namespace {

using namespace std::chrono_literals;

class ConnectionPoolTest : public test::DbTest {};

TEST_F(ConnectionPoolTest, LeasesDistinctConnectionsUpToTheMaximumThenWaits) {
  ConnectionPool pool(tmp_.url(), 2);
  auto a = pool.acquire();
  auto b = pool.acquire();
  EXPECT_NE(&*a, &*b);
  EXPECT_EQ(pool.open_connections(), 2u);
  std::atomic<bool> got = false;
  auto third = std::async(std::launch::async, [&] {
    auto c = pool.acquire();
    got = true;
    return &*c;
  });
  EXPECT_EQ(third.wait_for(200ms), std::future_status::timeout) << "a third connection was opened";
  EXPECT_FALSE(got);
  Database* returned = &*b;
  { auto gone = std::move(b); }  // given back
  EXPECT_EQ(third.get(), returned) << "the waiter got the returned connection";
  EXPECT_EQ(pool.open_connections(), 2u);
}

TEST_F(ConnectionPoolTest, AReturnedConnectionIsReusedAndNeverInATransaction) {
  ConnectionPool pool(tmp_.url(), 3);
  Database* first = nullptr;
  {
    auto lease = pool.acquire();
    first = &*lease;
    lease->exec("BEGIN");
    test::add_user(*lease, "uncommitted");
  }  // returned with its transaction open
  auto again = pool.acquire();
  EXPECT_EQ(&*again, first);
  EXPECT_FALSE(again->in_transaction());
  EXPECT_EQ(test::row_count(*again, "users"), 0) << "the open transaction was rolled back";
  EXPECT_EQ(pool.open_connections(), 1u);
}

TEST_F(ConnectionPoolTest, ConnectionsWorkSideBySideOnThreads) {
  ConnectionPool pool(tmp_.url(), 4);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      for (int k = 0; k < 25; ++k) {
        auto db = pool.acquire();
        char name[32];
        std::snprintf(name, sizeof name, "u%d_%d", t, k);
        test::add_user(*db, name);
      }
    });
  }
  for (auto& t : threads)
    t.join();
  EXPECT_EQ(test::row_count(db(), "users"), 100);
  EXPECT_LE(pool.open_connections(), 4u);
}

TEST(ConnectionPool, AFailedOpenThrowsAndGivesItsSlotBack) {
  INCISE_SQLITE_ONLY();
  ConnectionPool pool(DatabaseUrl::sqlite("/nonexistent-dir/x/incise.db"), 1);
  EXPECT_THROW(pool.acquire(), DbError);
  EXPECT_EQ(pool.open_connections(), 0u);
  EXPECT_THROW(pool.acquire(), DbError) << "the slot was free again (no wait)";
  EXPECT_THROW(ConnectionPool(DatabaseUrl::sqlite("a.db"), 0), std::invalid_argument);
}

}  // namespace
}  // namespace incise::db
