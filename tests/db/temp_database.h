#pragma once
// A real, fresh database with the embedded migrations applied, removed on destruction:
//  - by default an SQLite FILE in a fresh temporary directory (WAL mode needs a file, not
//    ":memory:");
//  - when INCISE_TEST_DATABASE holds a postgresql:// URL (the pg/ copies of the suite, with the
//    cluster that tests/support/postgres_cluster.sh starts), a fresh schema on that server, which
//    every connection of the test uses through its search_path.
// Plus small helpers that seed rows directly, so that tests which only need a user do not pay for
// an argon2id hash (~0.1 s each).
#include <gtest/gtest.h>

#include <unistd.h>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>

#include "db/database.h"
#include "db/migrations.h"
#include "db/statement.h"
#include "tests/support/temp_dir.h"

namespace incise::db::test {

using incise::test::TempDir;

// The engine the suite runs against: PostgreSQL when INCISE_TEST_DATABASE names a server.
inline Dialect test_dialect() {
  const char* url = std::getenv("INCISE_TEST_DATABASE");
  return url && *url ? DatabaseUrl::parse(url).dialect : Dialect::sqlite;
}

// Skips a test of SQLite itself (its files, pragmas, locks and result codes) in the pg/ run.
#define INCISE_SQLITE_ONLY()                                                 \
  do {                                                                       \
    if (::incise::db::test::test_dialect() != ::incise::db::Dialect::sqlite) \
      GTEST_SKIP() << "a test of SQLite itself";                             \
  } while (false)

class TempDatabase {
 public:
  enum class Schema { migrated, empty };

  explicit TempDatabase(Schema schema = Schema::migrated) : path_(dir_.path() / "incise.db") {
    if (test_dialect() == Dialect::postgresql) {
      static int count = 0;
      server_ = DatabaseUrl::parse(std::getenv("INCISE_TEST_DATABASE"));
      schema_ = "incise_t" + std::to_string(::getpid()) + "_" + std::to_string(++count);
      Database(server_).exec("CREATE SCHEMA " + schema_);
      url_ = server_;
      url_.target += (url_.target.find('?') == std::string::npos ? "?" : "&");
      url_.target += "options=-c%20search_path%3D" + schema_;
    } else {
      url_ = DatabaseUrl::sqlite(path_);
    }
    db_ = std::make_unique<Database>(url_);
    if (schema == Schema::migrated) apply_migrations(*db_);
  }
  ~TempDatabase() {
    db_.reset();
    if (schema_.empty()) return;
    try {
      Database(server_).exec("DROP SCHEMA " + schema_ + " CASCADE");
    } catch (const std::exception& e) {
      ADD_FAILURE() << "cannot drop the test schema " << schema_ << ": " << e.what();
    }
  }
  TempDatabase(const TempDatabase&) = delete;
  TempDatabase& operator=(const TempDatabase&) = delete;

  Database& db() { return *db_; }
  // The SQLite file (unused on PostgreSQL).
  const std::filesystem::path& path() const { return path_; }
  const std::filesystem::path& dir() const { return dir_.path(); }
  const DatabaseUrl& url() const { return url_; }
  // A second, independent connection to the same database (e.g. for another thread).
  std::unique_ptr<Database> open_another() const { return std::make_unique<Database>(url_); }

 private:
  TempDir dir_{"incise-db"};  // declared first, so it is removed after the connection has closed
  std::filesystem::path path_;
  DatabaseUrl server_;  // PostgreSQL: the cluster; schema_ is this test's own schema in it
  std::string schema_;
  DatabaseUrl url_;
  std::unique_ptr<Database> db_;
};

// A test with a fresh migrated database.
class DbTest : public ::testing::Test {
 protected:
  Database& db() { return tmp_.db(); }

  TempDatabase tmp_;
};

// Inserts a user without hashing a password (the hash is a placeholder nobody can log in with).
inline std::int64_t add_user(Database& db, std::string_view username,
                             std::string_view role = "trainee") {
  return db
      .prepare(
          "INSERT INTO users (username, display_name, role, password_hash, created_at) VALUES "
          "(?, ?, ?, 'not-a-hash', 0) RETURNING id")
      .bind(1, username)
      .bind(2, username)
      .bind(3, role)
      .insert();
}

// Inserts a station whose token hash is derived from its name (unique per name).
inline std::int64_t add_station(Database& db, std::string_view name) {
  return db
      .prepare(
          "INSERT INTO stations (name, location, token_hash, created_at) VALUES (?, '', ?, 0) "
          "RETURNING id")
      .bind(1, name)
      .bind_blob(2, std::span(reinterpret_cast<const std::uint8_t*>(name.data()), name.size()))
      .insert();
}

inline std::int64_t row_count(Database& db, std::string_view table) {
  auto q = db.prepare("SELECT COUNT(*) FROM " + std::string(table));
  q.step();
  return q.int64(0);
}

inline bool table_exists(Database& db, std::string_view table) {
  auto q = db.prepare(db.dialect() == Dialect::sqlite
                          ? "SELECT 1 FROM sqlite_master WHERE type = 'table' AND name = ?"
                          : "SELECT 1 FROM information_schema.tables WHERE table_schema = "
                            "current_schema() AND table_name = ?");
  q.bind(1, table);
  return q.step();
}

}  // namespace incise::db::test
