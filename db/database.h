#pragma once
// RAII connection to one database: an SQLite file (WAL journaling, foreign keys on, a busy
// timeout) or a PostgreSQL server (libpq). Both speak the SQL the repositories use; where the
// engines differ (locks, types) the difference lives below this class, in db/connection.h's
// engines, or is named by dialect(). One Database is used by one thread at a time (the caller
// serialises access).
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

#include "db/database_url.h"
#include "db/db_error.h"

struct sqlite3;

namespace incise::db {

class Statement;
namespace detail {
class Connection;
}

class Database {
 public:
  // Opens (creating if needed) the SQLite file at `path`; ":memory:" gives a private in-memory
  // database. Throws DbError with the path in the message when the file cannot be opened.
  explicit Database(const std::filesystem::path& path);
  // Opens the database the URL names; throws DbError naming the (redacted) URL on failure.
  explicit Database(const DatabaseUrl& url);
  ~Database();
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;

  Dialect dialect() const;
  // Runs one or more statements without parameters or results (schema, pragmas).
  void exec(std::string_view sql);
  // Placeholders are '?' (numbered in order) or '?N' on both engines.
  Statement prepare(std::string_view sql);

  // Rows changed by the last INSERT, UPDATE or DELETE.
  int changes() const;
  bool in_transaction() const;
  // False once the connection broke (a PostgreSQL server closed it); SQLite files stay usable.
  bool usable() const;
  // SQLite's own connection, for tests of SQLite itself; nullptr on PostgreSQL.
  sqlite3* handle() const;

 private:
  std::unique_ptr<detail::Connection> connection_;
};

// Throws the typed error for an SQLite result code (ConstraintError for constraint codes).
[[noreturn]] void throw_sqlite_error(sqlite3* db, int code, std::string_view context);

}  // namespace incise::db
