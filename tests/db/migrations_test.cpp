// Tests for db/migrations.h: migrations apply once, in order, each completely or not at all, and
// a database from a newer build is refused.
#include "db/migrations.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "db/recordings_repo.h"
#include "db/statement.h"
#include "db/training_repo.h"
#include "db/users_repo.h"
#include "temp_database.h"

namespace incise::db {
namespace {

using test::table_exists;
using test::TempDatabase;

// The column names of a table, in order.
std::vector<std::string> columns(Database& db, const std::string& table) {
  auto q = db.prepare(db.dialect() == Dialect::sqlite
                          ? "SELECT name FROM pragma_table_info(?) ORDER BY cid"
                          : "SELECT column_name FROM information_schema.columns WHERE table_schema "
                            "= current_schema() AND table_name = ? ORDER BY ordinal_position");
  q.bind(1, table);
  std::vector<std::string> out;
  while (q.step())
    out.push_back(q.text(0));
  return out;
}

int newest_embedded() {
  int newest = 0;
  for (const auto& m : embedded_migrations(test::test_dialect()))
    newest = std::max(newest, m.version);
  return newest;
}

class MigrationsTest : public ::testing::Test {
 protected:
  Database& db() { return tmp_.db(); }
  TempDatabase tmp_{TempDatabase::Schema::empty};
};

TEST(EmbeddedMigrations, AreNumberedFromOneInStrictlyIncreasingOrder) {
  const auto& all = embedded_migrations(test::test_dialect());
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
  EXPECT_EQ(apply_migrations(db()),
            static_cast<int>(embedded_migrations(test::test_dialect()).size()));
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
            static_cast<std::int64_t>(embedded_migrations(test::test_dialect()).size()));
}

TEST_F(MigrationsTest, OnlyNewerMigrationsAreApplied) {
  const std::vector<Migration> v1 = {{1, "001_a.sql", "CREATE TABLE a (x INTEGER)"}};
  const std::vector<Migration> v2 = {{1, "001_a.sql", "CREATE TABLE a (x INTEGER)"},
                                     {2, "002_b.sql", "CREATE TABLE b (x INTEGER)"}};
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
      {1, "001_good.sql", "CREATE TABLE good (x INTEGER)"},
      {2, "002_bad.sql",
       "CREATE TABLE partial (x INTEGER); INSERT INTO good VALUES (1); CREATE TABLEX broken (x);"},
      {3, "003_after.sql", "CREATE TABLE after (x INTEGER)"},
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
  fixed[1].sql = "CREATE TABLE partial (x INTEGER)";
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

TEST(EmbeddedMigrations, BothEnginesHaveTheSameNumberedList) {
  const auto& sqlite = embedded_migrations(Dialect::sqlite);
  const auto& postgresql = embedded_migrations(Dialect::postgresql);
  ASSERT_EQ(sqlite.size(), postgresql.size());
  for (std::size_t i = 0; i < sqlite.size(); ++i) {
    EXPECT_EQ(sqlite[i].version, postgresql[i].version);
    EXPECT_EQ(sqlite[i].name, postgresql[i].name);
  }
}

// On PostgreSQL (the pg/ run): the migrated schema has the tables and columns, in order, of the
// SQLite schema, so every repository's SQL reads the same columns on both.
TEST_F(MigrationsTest, BothEnginesBuildTheSameTablesAndColumns) {
  if (db().dialect() == Dialect::sqlite) GTEST_SKIP() << "compares PostgreSQL with SQLite";
  apply_migrations(db());
  test::TempDir dir{"incise-db"};
  Database sqlite(DatabaseUrl::sqlite(dir.path() / "reference.db"));
  apply_migrations(sqlite);
  auto tables = sqlite.prepare(
      "SELECT name FROM sqlite_master WHERE type = 'table' AND name NOT LIKE 'sqlite_%' ORDER BY "
      "name");
  int compared = 0;
  while (tables.step()) {
    const auto table = tables.text(0);
    EXPECT_EQ(columns(db(), table), columns(sqlite, table)) << table;
    ++compared;
  }
  EXPECT_GE(compared, 16);
}

TEST_F(MigrationsTest, FreshDatabaseGetsTheRecordingColumns) {
  apply_migrations(db());
  EXPECT_EQ(columns(db(), "recordings"),
            (std::vector<std::string>{"id", "session_id", "duration_s", "created_at", "scene",
                                      "scene_version", "seed", "tick_hz", "state",
                                      "final_state_hash", "material"}));
}

// A database a build with only 001 created, with a recording and a chunk in it, is upgraded in
// place: the old rows survive, read as complete recordings of an unknown scene.
TEST_F(MigrationsTest, RecordingsUpgradeFromTheInitialSchemaKeepsOldRows) {
  const auto& all = embedded_migrations(test::test_dialect());
  ASSERT_GE(all.size(), 2u);
  ASSERT_EQ(all[1].name, "002_recordings.sql");
  EXPECT_EQ(apply_migrations(db(), {all[0]}), 1);
  const auto user = test::add_user(db(), "ann");
  const std::int64_t session =
      db().prepare(
              "INSERT INTO sessions (trainee_id, task, state, created_at) VALUES (?, 't', "
              "'finished', 5) RETURNING id")
          .bind(1, user)
          .insert();
  const std::int64_t recording = db().prepare(
                                         "INSERT INTO recordings (session_id, duration_s, "
                                         "created_at) VALUES (?, 95.5, 7) RETURNING id")
                                     .bind(1, session)
                                     .insert();
  const std::vector<std::uint8_t> bytes = {1, 2, 3, 0, 255};
  db().prepare("INSERT INTO recording_chunks (recording_id, seq, t0_us, data) VALUES (?, 0, 0, ?)")
      .bind(1, recording)
      .bind_blob(2, bytes)
      .run();

  EXPECT_EQ(apply_migrations(db()), static_cast<int>(all.size()) - 1);
  EXPECT_EQ(schema_version(db()), newest_embedded());
  RecordingsRepo recordings(db());
  const auto meta = recordings.find(recording);
  ASSERT_TRUE(meta.has_value());
  EXPECT_EQ(meta->session_id, session);
  EXPECT_EQ(meta->duration_s, 95.5);
  EXPECT_EQ(meta->created_at, 7);
  EXPECT_EQ(meta->state, "complete");
  EXPECT_EQ(meta->scene, "");
  EXPECT_EQ(meta->scene_version, "");
  EXPECT_EQ(meta->seed, 0);
  EXPECT_EQ(meta->tick_hz, 0.0);
  const auto chunks = recordings.chunks(recording);
  ASSERT_EQ(chunks.size(), 1u);
  EXPECT_EQ(chunks[0].data, bytes);
  EXPECT_TRUE(recordings.unfinished().empty());

  // The new state column keeps its CHECK on upgraded rows too.
  auto bad = db().prepare("UPDATE recordings SET state = 'paused' WHERE id = ?");
  bad.bind(1, recording);
  EXPECT_THROW(bad.run(), ConstraintError);
}

// Before 006 every instructor saw every trainee: the upgrade assigns each existing trainee to each
// existing instructor, and nothing else; new users after it start unassigned.
TEST_F(MigrationsTest, InstructorAssignmentsUpgradeKeepsWhatInstructorsSaw) {
  const auto& all = embedded_migrations(test::test_dialect());
  const auto before = std::find_if(all.begin(), all.end(), [](const auto& m) {
    return m.name == "006_trainee_instructors.sql";
  });
  ASSERT_NE(before, all.end());
  const std::vector<Migration> older(all.begin(), before);
  EXPECT_EQ(apply_migrations(db(), older), static_cast<int>(older.size()));
  const auto ann = test::add_user(db(), "ann");
  const auto bob = test::add_user(db(), "bob");
  const auto ines = test::add_user(db(), "ines", "instructor");
  const auto ivo = test::add_user(db(), "ivo", "instructor");
  test::add_user(db(), "ada", "admin");

  apply_migrations(db());
  UsersRepo users(db());
  for (const auto trainee : {ann, bob}) {
    EXPECT_EQ(users.instructors_of(trainee), (std::vector<std::int64_t>{ines, ivo}));
  }
  EXPECT_TRUE(users.instructors_of(ines).empty());
  EXPECT_EQ(TrainingRepo(db()).sessions(TraineeScope::of_instructor(ines)).size(), 0u);

  // A session of ann is in ines's scope; after ann is reassigned to ivo alone, it is not.
  db().prepare(
          "INSERT INTO sessions (trainee_id, task, state, created_at) VALUES (?, 't', "
          "'finished', 5)")
      .bind(1, ann)
      .run();
  EXPECT_EQ(TrainingRepo(db()).sessions(TraineeScope::of_instructor(ines)).size(), 1u);
  users.set_instructors(ann, {ivo}, 9);
  EXPECT_FALSE(users.teaches(ines, ann));
  EXPECT_TRUE(users.teaches(ivo, ann));
  EXPECT_EQ(TrainingRepo(db()).sessions(TraineeScope::of_instructor(ines)).size(), 0u);
  EXPECT_EQ(TrainingRepo(db()).sessions(TraineeScope::of_instructor(ivo)).size(), 1u);
  EXPECT_EQ(TrainingRepo(db()).sessions(TraineeScope::of_trainee(bob)).size(), 0u);
  EXPECT_EQ(TrainingRepo(db()).sessions(TraineeScope::everyone()).size(), 1u);
}

}  // namespace
}  // namespace incise::db
