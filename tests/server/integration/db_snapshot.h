#pragma once
// Looks into the database of a running server (SQLite's data/incise.db, or the PostgreSQL
// database the pg/ suites give it), to check that a refused request changed nothing: every table
// but auth_sessions (which a request's sliding session expiry legitimately updates) and nodes
// (the heartbeats), dumped row by row.
#include <cstdint>
#include <string>

#include "db/database_url.h"

namespace incise::server::test {

// Every row of every table except auth_sessions, nodes and the engine's own, in a stable order, as
// text.
std::string snapshot_tables(const db::DatabaseUrl& database);

// The single integer (or text) that `sql` returns (e.g. a COUNT); "" for no row or NULL.
std::int64_t query_int(const db::DatabaseUrl& database, const std::string& sql);
std::string query_text(const db::DatabaseUrl& database, const std::string& sql);

}  // namespace incise::server::test
