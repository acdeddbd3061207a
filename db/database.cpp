#include "db/database.h"

#include <sqlite3.h>

#include "db/statement.h"

namespace incise::db {

Database::Database(const std::filesystem::path& path) {
  const int flags = SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX;
  const int rc = sqlite3_open_v2(path.c_str(), &db_, flags, nullptr);
  if (rc != SQLITE_OK) {
    const std::string message = "cannot open database " + path.string() + ": " +
                                (db_ ? sqlite3_errmsg(db_) : sqlite3_errstr(rc));
    sqlite3_close(db_);
    db_ = nullptr;
    throw DbError(rc, message);
  }
  sqlite3_extended_result_codes(db_, 1);
  sqlite3_busy_timeout(db_, 5000);
  try {
    exec("PRAGMA foreign_keys = ON");
    if (path != ":memory:") exec("PRAGMA journal_mode = WAL");
    // WAL with NORMAL sync is durable across application crashes; a power loss may drop the last
    // transactions, which the recorder tolerates (docs/architecture.md, "A live session, end to
    // end").
    exec("PRAGMA synchronous = NORMAL");
  } catch (const DbError& e) {
    // The destructor does not run for a throwing constructor: close here (e.g. not a database).
    sqlite3_close_v2(db_);
    db_ = nullptr;
    throw DbError(e.code(), "cannot open database " + path.string() + ": " + e.what());
  }
}

Database::~Database() {
  sqlite3_close_v2(db_);
}

void Database::exec(std::string_view sql) {
  char* error = nullptr;
  const std::string text(sql);
  const int rc = sqlite3_exec(db_, text.c_str(), nullptr, nullptr, &error);
  if (rc != SQLITE_OK) {
    std::string message = error ? error : sqlite3_errstr(rc);
    sqlite3_free(error);
    if ((rc & 0xff) == SQLITE_CONSTRAINT) throw ConstraintError(rc, message);
    throw DbError(rc, message);
  }
}

Statement Database::prepare(std::string_view sql) {
  return Statement(db_, sql);
}

std::int64_t Database::last_insert_id() const {
  return sqlite3_last_insert_rowid(db_);
}

int Database::changes() const {
  return sqlite3_changes(db_);
}

void throw_sqlite_error(sqlite3* db, int code, std::string_view context) {
  std::string message = std::string(context) + ": " + sqlite3_errmsg(db);
  if ((code & 0xff) == SQLITE_CONSTRAINT) throw ConstraintError(code, message);
  throw DbError(code, message);
}

}  // namespace incise::db
