#pragma once
// RAII connection to one SQLite database file, opened with WAL journaling, foreign keys on and a
// busy timeout. One Database is used by one thread at a time (the caller serialises access).
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "db/db_error.h"

struct sqlite3;

namespace incise::db {

class Statement;

class Database {
 public:
  // Opens (creating if needed) the file at `path`; ":memory:" gives a private in-memory database.
  // Throws DbError with the path in the message when the file cannot be opened.
  explicit Database(const std::filesystem::path& path);
  ~Database();
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;

  // Runs one or more statements without results (schema, pragmas).
  void exec(std::string_view sql);
  Statement prepare(std::string_view sql);

  std::int64_t last_insert_id() const;
  int changes() const;
  sqlite3* handle() const { return db_; }

 private:
  sqlite3* db_ = nullptr;
};

// Throws the typed error for an SQLite result code (ConstraintError for constraint codes).
[[noreturn]] void throw_sqlite_error(sqlite3* db, int code, std::string_view context);

}  // namespace incise::db
