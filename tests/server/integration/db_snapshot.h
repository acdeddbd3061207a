#pragma once
// Read-only looks into the database of a running server (its data/incise.db), to check that a
// refused request changed nothing: every table but auth_sessions (which a request's sliding
// session expiry legitimately updates), dumped row by row.
#include <cstdint>
#include <filesystem>
#include <string>

namespace incise::server::test {

// Every row of every table except auth_sessions and SQLite's own, in a stable order, as text.
std::string snapshot_tables(const std::filesystem::path& db_path);

// The single integer that `sql` returns (e.g. a COUNT).
std::int64_t query_int(const std::filesystem::path& db_path, const std::string& sql);

}  // namespace incise::server::test
