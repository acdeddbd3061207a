// Tests for db/database.h: the connection is opened in WAL mode with foreign keys on, and failures
// are reported as typed errors that name what failed.
#include "db/database.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <type_traits>

#include "db/statement.h"
#include "temp_database.h"

namespace incise::db {
namespace {

// Tests that need the migrated schema.
using DatabaseSchemaTest = test::DbTest;
using test::TempDatabase;
using test::TempDir;

std::string pragma_text(Database& db, const char* pragma) {
  auto q = db.prepare(std::string("PRAGMA ") + pragma);
  EXPECT_TRUE(q.step());
  return q.text(0);
}

TEST(Database, FileIsInWalModeWithForeignKeysOnAndABusyTimeout) {
  INCISE_SQLITE_ONLY();
  TempDir dir;
  Database db(dir.path() / "a.db");
  EXPECT_EQ(pragma_text(db, "journal_mode"), "wal");
  EXPECT_EQ(pragma_text(db, "foreign_keys"), "1");
  EXPECT_GT(std::stoi(pragma_text(db, "busy_timeout")), 0);
}

TEST(Database, SecondConnectionToTheFileIsAlsoConfigured) {
  INCISE_SQLITE_ONLY();
  TempDatabase tmp;
  auto other = tmp.open_another();
  EXPECT_EQ(pragma_text(*other, "journal_mode"), "wal");
  EXPECT_EQ(pragma_text(*other, "foreign_keys"), "1");
}

TEST(Database, CreatesTheFile) {
  INCISE_SQLITE_ONLY();
  TempDir dir;
  const auto path = dir.path() / "new.db";
  ASSERT_FALSE(std::filesystem::exists(path));
  Database db(path);
  db.exec("CREATE TABLE t (x)");
  EXPECT_TRUE(std::filesystem::exists(path));
}

TEST(Database, PathInAMissingDirectoryThrowsDbErrorNamingThePath) {
  INCISE_SQLITE_ONLY();
  TempDir dir;
  const auto path = dir.path() / "no-such-dir" / "x.db";
  try {
    Database db(path);
    FAIL() << "opened " << path;
  } catch (const DbError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    EXPECT_NE(e.code(), SQLITE_OK);
  }
  EXPECT_FALSE(std::filesystem::exists(path.parent_path()));
}

// A file that exists but is not a database "cannot be opened" just as well; the header promises
// the path in the message.
TEST(Database, FileThatIsNotADatabaseThrowsDbErrorNamingThePath) {
  INCISE_SQLITE_ONLY();
  TempDir dir;
  const auto path = dir.path() / "garbage.db";
  std::ofstream(path) << std::string(4096, 'x');
  try {
    Database db(path);
    db.exec("SELECT * FROM sqlite_master");
    FAIL() << "used a file that is not a database";
  } catch (const DbError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
}

TEST(Database, InMemoryDatabasesArePrivate) {
  INCISE_SQLITE_ONLY();
  Database a(":memory:");
  Database b(":memory:");
  a.exec("CREATE TABLE t (x)");
  EXPECT_TRUE(test::table_exists(a, "t"));
  EXPECT_FALSE(test::table_exists(b, "t"));
  EXPECT_EQ(pragma_text(a, "foreign_keys"), "1");
}

TEST(Database, ExecRunsSeveralStatements) {
  INCISE_SQLITE_ONLY();
  Database db(":memory:");
  db.exec("CREATE TABLE t (x); INSERT INTO t VALUES (1); INSERT INTO t VALUES (2);");
  EXPECT_EQ(test::row_count(db, "t"), 2);
}

TEST(Database, ExecOfBadSqlThrowsDbErrorWithSqlitesMessage) {
  INCISE_SQLITE_ONLY();
  Database db(":memory:");
  try {
    db.exec("CREATE TABLEX t (x)");
    FAIL();
  } catch (const ConstraintError&) {
    FAIL() << "a syntax error is not a constraint violation";
  } catch (const DbError& e) {
    EXPECT_EQ(e.code() & 0xff, SQLITE_ERROR);
    EXPECT_NE(std::string(e.what()).find("syntax error"), std::string::npos) << e.what();
  }
}

// db_error.h: a refused UNIQUE/CHECK/FOREIGN KEY write is a ConstraintError, whichever call ran it.
TEST(Database, ExecConstraintViolationThrowsConstraintError) {
  INCISE_SQLITE_ONLY();
  Database db(":memory:");
  db.exec("CREATE TABLE t (x UNIQUE); INSERT INTO t VALUES (1)");
  EXPECT_THROW(db.exec("INSERT INTO t VALUES (1)"), ConstraintError);
  EXPECT_EQ(test::row_count(db, "t"), 1);
}

TEST(Database, ExecCountsChanges) {
  INCISE_SQLITE_ONLY();
  Database db(":memory:");
  db.exec("CREATE TABLE t (id INTEGER PRIMARY KEY, x)");
  db.exec("INSERT INTO t (id, x) VALUES (41, 'a'); INSERT INTO t (x) VALUES ('b')");
  db.exec("UPDATE t SET x = 'c'");
  EXPECT_EQ(db.changes(), 2);
  db.exec("DELETE FROM t WHERE id = 1000");
  EXPECT_EQ(db.changes(), 0);
}

TEST_F(DatabaseSchemaTest, ForeignKeysAreEnforced) {
  // A booking of a station that does not exist.
  const auto user = test::add_user(db(), "ann");
  auto insert = db().prepare(
      "INSERT INTO bookings (station_id, user_id, starts_at, ends_at, created_at) VALUES "
      "(999, ?, 0, 10, 0)");
  insert.bind(1, user);
  try {
    insert.run();
    FAIL() << "foreign key not enforced";
  } catch (const ConstraintError& e) {
    if (db().dialect() == Dialect::sqlite) {
      EXPECT_EQ(e.code(), SQLITE_CONSTRAINT_FOREIGNKEY);
    } else {
      EXPECT_EQ(e.sqlstate(), "23503") << "foreign_key_violation";
    }
  }
  EXPECT_EQ(test::row_count(db(), "bookings"), 0);
}

TEST_F(DatabaseSchemaTest, DeletingAUserCascadesToItsLoginSessions) {
  const auto user = test::add_user(db(), "ann");
  const std::uint8_t token[] = {1};
  db().prepare("INSERT INTO auth_sessions VALUES (?, ?, 0, 10)")
      .bind_blob(1, token)
      .bind(2, user)
      .run();
  db().prepare("DELETE FROM users WHERE id = ?").bind(1, user).run();
  EXPECT_EQ(test::row_count(db(), "auth_sessions"), 0);
}

TEST(Database, ThrowSqliteErrorTypesByPrimaryCode) {
  INCISE_SQLITE_ONLY();
  Database db(":memory:");
  try {
    throw_sqlite_error(db.handle(), SQLITE_CONSTRAINT_UNIQUE, "insert user");
  } catch (const ConstraintError& e) {
    EXPECT_EQ(e.code(), SQLITE_CONSTRAINT_UNIQUE);
    EXPECT_EQ(std::string(e.what()).rfind("insert user", 0), 0u) << e.what();
  }
  try {
    throw_sqlite_error(db.handle(), SQLITE_BUSY, "step");
  } catch (const ConstraintError&) {
    FAIL() << "SQLITE_BUSY is not a constraint violation";
  } catch (const DbError& e) {
    EXPECT_EQ(e.code(), SQLITE_BUSY);
  }
}

TEST(Database, ErrorTypesFormAHierarchy) {
  // Callers catch DbError for every storage failure; ConstraintError is one kind of it.
  EXPECT_TRUE((std::is_base_of_v<DbError, ConstraintError>));
  EXPECT_FALSE((std::is_base_of_v<DbError, NotFound>));
  EXPECT_FALSE((std::is_base_of_v<DbError, Conflict>));
}

}  // namespace
}  // namespace incise::db
