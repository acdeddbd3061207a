#include "db/transaction.h"

#include <sqlite3.h>

namespace incise::db {

Transaction::Transaction(Database& db, Mode mode)
    : db_(db), nested_(sqlite3_get_autocommit(db.handle()) == 0) {
  if (nested_) {
    db_.exec("SAVEPOINT incise_nested");
  } else {
    db_.exec(mode == Mode::immediate ? "BEGIN IMMEDIATE" : "BEGIN");
  }
}

Transaction::~Transaction() {
  if (done_) return;
  try {
    db_.exec(nested_ ? "ROLLBACK TO incise_nested; RELEASE incise_nested" : "ROLLBACK");
  } catch (...) {
    // A destructor never throws; SQLite has already rolled back if ROLLBACK itself fails.
  }
}

void Transaction::commit() {
  db_.exec(nested_ ? "RELEASE incise_nested" : "COMMIT");
  done_ = true;
}

}  // namespace incise::db
