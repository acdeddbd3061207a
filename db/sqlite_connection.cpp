// The SQLite engine behind Database: one sqlite3 connection in WAL mode with foreign keys on and
// a busy timeout; statements are sqlite3_stmt.
#include <sqlite3.h>

#include "db/connection.h"
#include "db/database.h"

namespace incise::db {

void throw_sqlite_error(sqlite3* db, int code, std::string_view context) {
  std::string message = std::string(context) + ": " + sqlite3_errmsg(db);
  if ((code & 0xff) == SQLITE_CONSTRAINT) throw ConstraintError(code, message);
  throw DbError(code, message);
}

namespace detail {
namespace {

class SqliteCursor final : public Cursor {
 public:
  SqliteCursor(sqlite3* db, std::string_view sql) : db_(db) {
    const int rc =
        sqlite3_prepare_v2(db_, sql.data(), static_cast<int>(sql.size()), &stmt_, nullptr);
    if (rc != SQLITE_OK) throw_sqlite_error(db_, rc, "prepare");
  }
  ~SqliteCursor() override { sqlite3_finalize(stmt_); }
  SqliteCursor(const SqliteCursor&) = delete;
  SqliteCursor& operator=(const SqliteCursor&) = delete;

  void bind_int64(int index, std::int64_t value) override {
    check_bind(sqlite3_bind_int64(stmt_, index, value));
  }
  void bind_double(int index, double value) override {
    check_bind(sqlite3_bind_double(stmt_, index, value));
  }
  void bind_text(int index, std::string_view text) override {
    // An empty string_view may have a null data(), which SQLite would bind as NULL.
    check_bind(sqlite3_bind_text(stmt_, index, text.data() ? text.data() : "",
                                 static_cast<int>(text.size()), SQLITE_TRANSIENT));
  }
  void bind_blob(int index, std::span<const std::uint8_t> bytes) override {
    // An empty span may have a null data(), which SQLite would bind as NULL: a zero-length blob.
    check_bind(bytes.empty() ? sqlite3_bind_zeroblob(stmt_, index, 0)
                             : sqlite3_bind_blob(stmt_, index, bytes.data(),
                                                 static_cast<int>(bytes.size()), SQLITE_TRANSIENT));
  }
  void bind_null(int index) override { check_bind(sqlite3_bind_null(stmt_, index)); }

  bool step() override {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    sqlite3_reset(stmt_);
    throw_sqlite_error(db_, rc, "step");
  }
  void reset() override {
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
  }

  int columns() const override { return sqlite3_column_count(stmt_); }
  bool is_null(int column) const override {
    return sqlite3_column_type(stmt_, column) == SQLITE_NULL;
  }
  std::int64_t int64(int column) const override { return sqlite3_column_int64(stmt_, column); }
  double real(int column) const override { return sqlite3_column_double(stmt_, column); }
  std::string text(int column) const override {
    const auto* p = reinterpret_cast<const char*>(sqlite3_column_text(stmt_, column));
    return p ? std::string(p, static_cast<size_t>(sqlite3_column_bytes(stmt_, column))) : "";
  }
  std::vector<std::uint8_t> blob(int column) const override {
    const auto* p = static_cast<const std::uint8_t*>(sqlite3_column_blob(stmt_, column));
    return p ? std::vector<std::uint8_t>(p, p + sqlite3_column_bytes(stmt_, column))
             : std::vector<std::uint8_t>{};
  }

 private:
  void check_bind(int rc) const {
    if (rc != SQLITE_OK) throw_sqlite_error(db_, rc, "bind");
  }

  sqlite3* db_;
  sqlite3_stmt* stmt_ = nullptr;
};

class SqliteConnection final : public Connection {
 public:
  explicit SqliteConnection(const std::filesystem::path& path) {
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
      // WAL with NORMAL sync is durable across application crashes; a power loss may drop the
      // last transactions, which the recorder tolerates (docs/architecture.md, "A live session,
      // end to end").
      exec("PRAGMA synchronous = NORMAL");
    } catch (const DbError& e) {
      // The destructor does not run for a throwing constructor: close here (not a database).
      sqlite3_close_v2(db_);
      db_ = nullptr;
      throw DbError(e.code(), "cannot open database " + path.string() + ": " + e.what());
    }
  }
  ~SqliteConnection() override { sqlite3_close_v2(db_); }
  SqliteConnection(const SqliteConnection&) = delete;
  SqliteConnection& operator=(const SqliteConnection&) = delete;

  Dialect dialect() const override { return Dialect::sqlite; }

  void exec(std::string_view sql) override {
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

  std::unique_ptr<Cursor> prepare(std::string_view sql) override {
    return std::make_unique<SqliteCursor>(db_, sql);
  }
  int changes() const override { return sqlite3_changes(db_); }
  bool in_transaction() const override { return sqlite3_get_autocommit(db_) == 0; }
  bool usable() const override { return true; }
  void* native_handle() const override { return db_; }

 private:
  sqlite3* db_ = nullptr;
};

}  // namespace

std::unique_ptr<Connection> open_sqlite(const std::filesystem::path& path) {
  return std::make_unique<SqliteConnection>(path);
}

}  // namespace detail
}  // namespace incise::db
