#include "db_snapshot.h"

#include <sqlite3.h>

#include <memory>
#include <stdexcept>
#include <vector>

namespace incise::server::test {

namespace {

struct Closer {
  void operator()(sqlite3* db) const { sqlite3_close_v2(db); }
};
struct Finalizer {
  void operator()(sqlite3_stmt* s) const { sqlite3_finalize(s); }
};
using Connection = std::unique_ptr<sqlite3, Closer>;
using Query = std::unique_ptr<sqlite3_stmt, Finalizer>;

Connection open_read_only(const std::filesystem::path& path) {
  sqlite3* db = nullptr;
  const int rc = sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
  Connection connection(db);
  if (rc != SQLITE_OK) {
    throw std::runtime_error("open " + path.string() + ": " +
                             (db ? sqlite3_errmsg(db) : sqlite3_errstr(rc)));
  }
  sqlite3_busy_timeout(db, 5000);
  return connection;
}

Query prepare(sqlite3* db, const std::string& sql) {
  sqlite3_stmt* stmt = nullptr;
  if (sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt, nullptr) != SQLITE_OK) {
    throw std::runtime_error("prepare '" + sql + "': " + sqlite3_errmsg(db));
  }
  return Query(stmt);
}

bool step(sqlite3* db, sqlite3_stmt* stmt) {
  const int rc = sqlite3_step(stmt);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  throw std::runtime_error(std::string("step: ") + sqlite3_errmsg(db));
}

}  // namespace

std::string snapshot_tables(const std::filesystem::path& db_path) {
  const auto db = open_read_only(db_path);
  // One read transaction, so that the dump is one consistent state.
  sqlite3_exec(db.get(), "BEGIN", nullptr, nullptr, nullptr);
  std::vector<std::string> tables;
  {
    const auto q = prepare(db.get(),
                           "SELECT name FROM sqlite_master WHERE type = 'table' AND name NOT LIKE "
                           "'sqlite_%' AND name != 'auth_sessions' ORDER BY name");
    while (step(db.get(), q.get()))
      tables.emplace_back(reinterpret_cast<const char*>(sqlite3_column_text(q.get(), 0)));
  }
  std::string out;
  for (const auto& table : tables) {
    out += "[" + table + "]\n";
    const auto q = prepare(db.get(), "SELECT * FROM \"" + table + "\" ORDER BY 1");
    const int columns = sqlite3_column_count(q.get());
    while (step(db.get(), q.get())) {
      for (int c = 0; c < columns; ++c) {
        if (c > 0) out += "|";
        if (sqlite3_column_type(q.get(), c) == SQLITE_NULL) {
          out += "NULL";
        } else {
          const auto* bytes = static_cast<const char*>(sqlite3_column_blob(q.get(), c));
          out.append(bytes ? bytes : "",
                     static_cast<std::size_t>(sqlite3_column_bytes(q.get(), c)));
        }
      }
      out += "\n";
    }
  }
  sqlite3_exec(db.get(), "COMMIT", nullptr, nullptr, nullptr);
  return out;
}

std::int64_t query_int(const std::filesystem::path& db_path, const std::string& sql) {
  const auto db = open_read_only(db_path);
  const auto q = prepare(db.get(), sql);
  if (!step(db.get(), q.get())) throw std::runtime_error("no row from '" + sql + "'");
  return sqlite3_column_int64(q.get(), 0);
}

}  // namespace incise::server::test
