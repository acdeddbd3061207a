#pragma once
// Numbered schema migrations (db/migrations/NNN_name.sql for SQLite, db/migrations/postgresql/ with
// the same numbers and names for PostgreSQL), embedded at build time and applied in order at
// start-up, each in its own IMMEDIATE transaction (so two server nodes starting together apply
// each migration once). The applied versions are kept in schema_migrations: applying is idempotent.
#include <string>
#include <vector>

#include "db/database.h"

namespace incise::db {

struct Migration {
  int version;
  std::string name;
  std::string sql;
};

const std::vector<Migration>& embedded_migrations(Dialect dialect = Dialect::sqlite);

// Applies every migration newer than the database's version; returns how many were applied.
// Throws DbError when the database is newer than this build (it knows no such schema).
int apply_migrations(Database& db, const std::vector<Migration>& migrations);
// The embedded migrations of the database's own engine.
int apply_migrations(Database& db);

int schema_version(Database& db);

}  // namespace incise::db
