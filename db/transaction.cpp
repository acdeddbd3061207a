#include "db/transaction.h"

namespace incise::db {

namespace {
// The key of the one PostgreSQL advisory lock that IMMEDIATE transactions take: it serialises
// read-check-write sequences across every connection and every server node, as SQLite's
// BEGIN IMMEDIATE does across connections to one file. Readers and plain writers never wait on it.
// READ COMMITTED whatever the server's default: each statement after the lock then sees what the
// previous holder committed (a REPEATABLE READ snapshot would be taken before the lock wait).
constexpr const char* kBeginImmediatePostgresql =
    "BEGIN ISOLATION LEVEL READ COMMITTED; SELECT pg_advisory_xact_lock(7316240118)";
}  // namespace

Transaction::Transaction(Database& db, Mode mode) : db_(db), nested_(db.in_transaction()) {
  if (nested_) {
    db_.exec("SAVEPOINT incise_nested");
  } else if (db_.dialect() == Dialect::postgresql) {
    try {
      db_.exec(mode == Mode::immediate ? kBeginImmediatePostgresql : "BEGIN");
    } catch (...) {
      // The lock wait timed out after BEGIN: no destructor runs for a throwing constructor, and a
      // connection left in a failed transaction would refuse every later statement.
      try {
        db_.exec("ROLLBACK");
      } catch (...) {
      }
      throw;
    }
  } else {
    db_.exec(mode == Mode::immediate ? "BEGIN IMMEDIATE" : "BEGIN");
  }
}

Transaction::~Transaction() {
  if (done_) return;
  try {
    db_.exec(nested_ ? "ROLLBACK TO incise_nested; RELEASE incise_nested" : "ROLLBACK");
  } catch (...) {
    // A destructor never throws; the engine has already rolled back if ROLLBACK itself fails.
  }
}

void Transaction::commit() {
  db_.exec(nested_ ? "RELEASE incise_nested" : "COMMIT");
  done_ = true;
}

}  // namespace incise::db
