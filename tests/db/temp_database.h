#pragma once
// A real database FILE in a fresh temporary directory (WAL mode needs a file, not ":memory:"),
// with the embedded migrations applied; the directory and everything in it is removed on
// destruction. Plus small helpers that seed rows directly, so that tests which only need a user
// do not pay for an argon2id hash (~0.1 s each).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <memory>
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

class TempDatabase {
 public:
  enum class Schema { migrated, empty };

  explicit TempDatabase(Schema schema = Schema::migrated)
      : path_(dir_.path() / "incise.db"), db_(std::make_unique<Database>(path_)) {
    if (schema == Schema::migrated) apply_migrations(*db_);
  }

  Database& db() { return *db_; }
  const std::filesystem::path& path() const { return path_; }
  const std::filesystem::path& dir() const { return dir_.path(); }
  // A second, independent connection to the same file (e.g. for another thread).
  std::unique_ptr<Database> open_another() const { return std::make_unique<Database>(path_); }

 private:
  TempDir dir_{"incise-db"};  // declared first, so it is removed after the connection has closed
  std::filesystem::path path_;
  std::unique_ptr<Database> db_;
};

// A test with a fresh migrated database file.
class DbTest : public ::testing::Test {
 protected:
  Database& db() { return tmp_.db(); }

  TempDatabase tmp_;
};

// Inserts a user without hashing a password (the hash is a placeholder nobody can log in with).
inline std::int64_t add_user(Database& db, std::string_view username,
                             std::string_view role = "trainee") {
  db.prepare(
        "INSERT INTO users (username, display_name, role, password_hash, created_at) VALUES "
        "(?, ?, ?, 'not-a-hash', 0)")
      .bind(1, username)
      .bind(2, username)
      .bind(3, role)
      .run();
  return db.last_insert_id();
}

// Inserts a station whose token hash is derived from its name (unique per name).
inline std::int64_t add_station(Database& db, std::string_view name) {
  db.prepare(
        "INSERT INTO stations (name, location, token_hash, created_at) VALUES (?, '', "
        "CAST(? AS BLOB), 0)")
      .bind(1, name)
      .bind(2, name)
      .run();
  return db.last_insert_id();
}

inline std::int64_t row_count(Database& db, std::string_view table) {
  auto q = db.prepare("SELECT COUNT(*) FROM " + std::string(table));
  q.step();
  return q.int64(0);
}

inline bool table_exists(Database& db, std::string_view table) {
  auto q = db.prepare("SELECT 1 FROM sqlite_master WHERE type = 'table' AND name = ?");
  q.bind(1, table);
  return q.step();
}

}  // namespace incise::db::test
