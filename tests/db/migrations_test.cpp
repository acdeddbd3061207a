// Tests for db/migrations.h: migrations apply once, in order, each completely or not at all, and
// a database from a newer build is refused.
#include "db/migrations.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "db/statement.h"
#include "temp_database.h"

namespace incise::db {
namespace {

using test::table_exists;
using test::TempDatabase;

int newest_embedded() {
  int newest = 0;
  for (const auto& m : embedded_migrations())
    newest = std::max(newest, m.version);
  return newest;
}

class MigrationsTest : public ::testing::Test {
 protected:
  Database& db() { return tmp_.db(); }
  TempDatabase tmp_{TempDatabase::Schema::empty};
};

TEST(EmbeddedMigrations, AreNumberedFromOneInStrictlyIncreasingOrder) {
  const auto& all = embedded_migrations();
  ASSERT_FALSE(all.empty());
  EXPECT_EQ(all.front().version, 1);
  for (std::size_t i = 1; i < all.size(); ++i)
    EXPECT_LT(all[i - 1].version, all[i].version) << all[i].name;
  for (const auto& m : all) {
    EXPECT_FALSE(m.sql.empty()) << m.name;
    EXPECT_EQ(std::stoi(m.name), m.version) << "file name " << m.name << " carries the number";
  }
}

TEST_F(MigrationsTest, FreshDatabaseHasVersionZero) {
  EXPECT_EQ(schema_version(db()), 0);
}

TEST_F(MigrationsTest, ApplyingOnceCreatesEveryTable) {
  EXPECT_EQ(apply_migrations(db()), static_cast<int>(embedded_migrations().size()));
  for (const char* table :
       {"users", "auth_sessions", "stations", "bookings", "curricula", "sessions", "recordings",
        "recording_chunks", "scores", "audit_log", "schema_migrations"}) {
    EXPECT_TRUE(table_exists(db(), table)) << table;
  }
  EXPECT_EQ(schema_version(db()), newest_embedded());
}

TEST_F(MigrationsTest, ApplyingAgainAppliesNothing) {
  apply_migrations(db());
  EXPECT_EQ(apply_migrations(db()), 0);
  // Also through a new connection, as at the next server start.
  auto reopened = tmp_.open_another();
  EXPECT_EQ(apply_migrations(*reopened), 0);
  EXPECT_EQ(schema_version(*reopened), newest_embedded());
  EXPECT_EQ(test::row_count(db(), "schema_migrations"),
            static_cast<std::int64_t>(embedded_migrations().size()));
}

TEST_F(MigrationsTest, OnlyNewerMigrationsAreApplied) {
  const std::vector<Migration> v1 = {{1, "001_a.sql", "CREATE TABLE a (x)"}};
  const std::vector<Migration> v2 = {{1, "001_a.sql", "CREATE TABLE a (x)"},
                                     {2, "002_b.sql", "CREATE TABLE b (x)"}};
  EXPECT_EQ(apply_migrations(db(), v1), 1);
  EXPECT_EQ(schema_version(db()), 1);
  // Running 001 again would fail ("table a already exists"), so success shows it was skipped.
  EXPECT_EQ(apply_migrations(db(), v2), 1);
  EXPECT_EQ(schema_version(db()), 2);
  EXPECT_TRUE(table_exists(db(), "b"));
}

TEST_F(MigrationsTest, DatabaseNewerThanTheBuildIsRefused) {
  apply_migrations(db());
  const int future = newest_embedded() + 1;
  db().prepare("INSERT INTO schema_migrations (version, name, applied_at) VALUES (?, 'x', 0)")
      .bind(1, future)
      .run();
  try {
    apply_migrations(db());
    FAIL() << "accepted a database from a newer build";
  } catch (const DbError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("newer"), std::string::npos) << message;
    EXPECT_NE(message.find(std::to_string(future)), std::string::npos) << message;
    EXPECT_NE(message.find(std::to_string(newest_embedded())), std::string::npos) << message;
  }
  EXPECT_EQ(schema_version(db()), future);
}

TEST_F(MigrationsTest, FailingMigrationRollsBackCompletely) {
  const std::vector<Migration> migrations = {
      {1, "001_good.sql", "CREATE TABLE good (x)"},
      {2, "002_bad.sql",
       "CREATE TABLE partial (x); INSERT INTO good VALUES (1); CREATE TABLEX broken (x);"},
      {3, "003_after.sql", "CREATE TABLE after (x)"},
  };
  try {
    apply_migrations(db(), migrations);
    FAIL() << "bad SQL was accepted";
  } catch (const DbError& e) {
    EXPECT_NE(std::string(e.what()).find("002_bad.sql"), std::string::npos) << e.what();
  }
  EXPECT_EQ(schema_version(db()), 1) << "the good migration before stays applied";
  EXPECT_TRUE(table_exists(db(), "good"));
  EXPECT_FALSE(table_exists(db(), "partial")) << "partial schema change survived";
  EXPECT_EQ(test::row_count(db(), "good"), 0) << "partial data change survived";
  EXPECT_FALSE(table_exists(db(), "after")) << "a later migration ran after a failure";

  // Once fixed, the failed migration and the ones after it apply.
  auto fixed = migrations;
  fixed[1].sql = "CREATE TABLE partial (x)";
  EXPECT_EQ(apply_migrations(db(), fixed), 2);
  EXPECT_EQ(schema_version(db()), 3);
}

TEST_F(MigrationsTest, EmbeddedSchemaEnforcesItsChecks) {
  apply_migrations(db());
  EXPECT_THROW(test::add_user(db(), "ann", "superuser"), ConstraintError);
  const auto user = test::add_user(db(), "ann");
  const auto station = test::add_station(db(), "s1");
  auto q = db().prepare(
      "INSERT INTO bookings (station_id, user_id, starts_at, ends_at, created_at) VALUES (?, ?, "
      "10, 10, 0)");
  q.bind(1, station).bind(2, user);
  EXPECT_THROW(q.run(), ConstraintError) << "an empty interval";
}

}  // namespace
}  // namespace incise::db
