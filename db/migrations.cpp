#include "db/migrations.h"

#include <algorithm>
#include <ctime>

#include <sqlite3.h>

#include "db/statement.h"
#include "db/transaction.h"

namespace incise::db {

int schema_version(Database& db) {
  db.exec(
      "CREATE TABLE IF NOT EXISTS schema_migrations (version INTEGER PRIMARY KEY, name TEXT NOT "
      "NULL, applied_at BIGINT NOT NULL)");
  auto q = db.prepare("SELECT COALESCE(MAX(version), 0) FROM schema_migrations");
  q.step();
  return static_cast<int>(q.int64(0));
}

int apply_migrations(Database& db) {
  return apply_migrations(db, embedded_migrations(db.dialect()));
}

int apply_migrations(Database& db, const std::vector<Migration>& migrations) {
  int newest_known = 0;
  for (const auto& m : migrations)
    newest_known = std::max(newest_known, m.version);
  {
    Transaction tx(db);
    const int current = schema_version(db);
    if (current > newest_known) {
      throw DbError(SQLITE_ERROR, "database schema version " + std::to_string(current) +
                                      " is newer than this build knows (" +
                                      std::to_string(newest_known) + ")");
    }
    tx.commit();
  }
  int applied = 0;
  for (const auto& m : migrations) {
    // Each migration checks the version again inside its own IMMEDIATE transaction: another node
    // may have applied it meanwhile.
    Transaction tx(db);
    if (m.version <= schema_version(db)) continue;
    try {
      db.exec(m.sql);
    } catch (const DbError& e) {
      throw DbError(e.code(), "migration " + m.name + " failed: " + e.what(), e.sqlstate());
    }
    db.prepare("INSERT INTO schema_migrations (version, name, applied_at) VALUES (?, ?, ?)")
        .bind(1, m.version)
        .bind(2, m.name)
        .bind(3, static_cast<std::int64_t>(std::time(nullptr)))
        .run();
    tx.commit();
    ++applied;
  }
  return applied;
}

}  // namespace incise::db
