#include "db_snapshot.h"

#include <stdexcept>
#include <vector>

#include "db/database.h"
#include "db/statement.h"
#include "db/transaction.h"

namespace incise::server::test {

std::string snapshot_tables(const db::DatabaseUrl& database) {
  db::Database db(database);
  // One read transaction, so that the dump is one consistent state.
  db::Transaction read(db, db::Transaction::Mode::deferred);
  if (db.dialect() == db::Dialect::postgresql) {
    db.exec("SET TRANSACTION ISOLATION LEVEL REPEATABLE READ");
  }
  std::vector<std::string> tables;
  {
    auto q = db.prepare(
        db.dialect() == db::Dialect::sqlite
            ? "SELECT name FROM sqlite_master WHERE type = 'table' AND name NOT "
              "LIKE 'sqlite_%' AND name NOT IN ('auth_sessions', 'nodes') ORDER BY name"
            : "SELECT table_name FROM information_schema.tables WHERE table_schema "
              "= current_schema() AND table_name NOT IN ('auth_sessions', 'nodes') ORDER BY 1");
    while (q.step())
      tables.push_back(q.text(0));
  }
  std::string out;
  for (const auto& table : tables) {
    out += "[" + table + "]\n";
    auto q = db.prepare("SELECT * FROM \"" + table + "\" ORDER BY 1");
    while (q.step()) {
      for (int c = 0; c < q.columns(); ++c) {
        if (c > 0) out += "|";
        out += q.is_null(c) ? "NULL" : q.text(c);
      }
      out += "\n";
    }
  }
  return out;
}

std::int64_t query_int(const db::DatabaseUrl& database, const std::string& sql) {
  db::Database db(database);
  auto q = db.prepare(sql);
  if (!q.step()) throw std::runtime_error("no row from '" + sql + "'");
  return q.int64(0);
}

std::string query_text(const db::DatabaseUrl& database, const std::string& sql) {
  db::Database db(database);
  auto q = db.prepare(sql);
  return q.step() ? q.text(0) : "";
}

}  // namespace incise::server::test
