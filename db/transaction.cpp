#include "db/transaction.h"

namespace incise::db {

namespace {
// The key of the one PostgreSQL advisory lock that IMMEDIATE transactions take: it serialises
// read-check-write sequences across every connection and every server node, as SQLite's
// BEGIN IMMEDIATE does across connections to one file. Readers and plain writers never wait on it.
constexpr const char* kBeginImmediatePostgresql = "BEGIN; SELECT pg_advisory_xact_lock(7316240118)";
}  // namespace

Transaction::Transaction(Database& db, Mode mode) : db_(db), nested_(db.in_transaction()) {
  if (nested_) {
    db_.exec("SAVEPOINT incise_nested");
  } else if (db_.dialect() == Dialect::postgresql) {
    db_.exec(mode == Mode::immediate ? kBeginImmediatePostgresql : "BEGIN");
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
