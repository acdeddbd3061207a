#pragma once
// A transaction that rolls back unless committed (after SQLiteCpp's Transaction). IMMEDIATE takes
// the write lock at the start, so a read-check-write sequence (e.g. booking conflict checks) cannot
// interleave with another IMMEDIATE writer: SQLite's BEGIN IMMEDIATE, or on PostgreSQL one
// transaction-scoped advisory lock shared by every node. Inside another transaction it is a
// savepoint of it: committing keeps its changes for the outer transaction to commit, destroying it
// undoes only its own.
#include "db/database.h"

namespace incise::db {

class Transaction {
 public:
  enum class Mode { deferred, immediate };
  explicit Transaction(Database& db, Mode mode = Mode::immediate);
  ~Transaction();
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;

  void commit();

 private:
  Database& db_;
  bool nested_ = false;  // opened inside another transaction: a SAVEPOINT
  bool done_ = false;
};

}  // namespace incise::db
