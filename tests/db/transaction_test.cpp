// Tests for db/transaction.h: a transaction rolls back unless committed, also when the scope is
// left by an exception, and IMMEDIATE mode holds the write lock from the start.
#include "db/transaction.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <stdexcept>

#include "db/statement.h"
#include "temp_database.h"

namespace incise::db {
namespace {

using test::row_count;

class TransactionTest : public ::testing::Test {
 protected:
  TransactionTest() { db().exec("CREATE TABLE t (x INTEGER UNIQUE)"); }
  Database& db() { return tmp_.db(); }
  void insert(std::int64_t x) { db().prepare("INSERT INTO t VALUES (?)").bind(1, x).run(); }
  bool has(std::int64_t x) {
    auto q = db().prepare("SELECT 1 FROM t WHERE x = ?");
    q.bind(1, x);
    return q.step();
  }

  test::TempDatabase tmp_{test::TempDatabase::Schema::empty};
};

// Makes a connection give up on a lock at once instead of waiting 5 s.
void fail_fast(Database& db) {
  if (db.dialect() == Dialect::sqlite) {
    sqlite3_busy_timeout(db.handle(), 0);
  } else {
    db.exec("SET lock_timeout = 1");
  }
}

// SQLite's "database is locked", or PostgreSQL's lock_not_available.
bool is_busy(const DbError& e) {
  return (e.code() & 0xff) == SQLITE_BUSY || e.sqlstate() == "55P03";
}

TEST_F(TransactionTest, RollsBackUnlessCommitted) {
  {
    Transaction tx(db());
    insert(1);
    EXPECT_TRUE(has(1)) << "visible inside the transaction";
  }
  EXPECT_FALSE(has(1));
  {
    Transaction tx(db());
    insert(2);
    tx.commit();
  }
  EXPECT_TRUE(has(2));
}

TEST_F(TransactionTest, CommittedDataIsVisibleToAnotherConnection) {
  auto other = tmp_.open_another();
  {
    Transaction tx(db());
    insert(1);
    EXPECT_EQ(row_count(*other, "t"), 0) << "uncommitted data leaked";
    tx.commit();
  }
  EXPECT_EQ(row_count(*other, "t"), 1);
}

TEST_F(TransactionTest, ExceptionInsideTheScopeRollsBackOnlyThatScope) {
  insert(1);
  {
    Transaction tx(db());
    insert(2);
    tx.commit();
  }
  try {
    Transaction tx(db());
    insert(3);
    insert(4);
    throw std::runtime_error("failure half-way");
  } catch (const std::runtime_error&) {
  }
  EXPECT_TRUE(has(1));
  EXPECT_TRUE(has(2));
  EXPECT_FALSE(has(3));
  EXPECT_FALSE(has(4));
  EXPECT_EQ(row_count(db(), "t"), 2);
  // The connection is usable again, outside any transaction.
  EXPECT_FALSE(db().in_transaction());
  insert(5);
  EXPECT_TRUE(has(5));
}

TEST_F(TransactionTest, ConstraintErrorInsideTheScopeUndoesEarlierWrites) {
  insert(1);
  EXPECT_THROW(
      {
        Transaction tx(db());
        insert(2);
        insert(1);  // duplicate
        tx.commit();
      },
      ConstraintError);
  EXPECT_FALSE(has(2));
  EXPECT_EQ(row_count(db(), "t"), 1);
}

TEST_F(TransactionTest, CommitEndsTheTransaction) {
  Transaction tx(db());
  EXPECT_TRUE(db().in_transaction());
  tx.commit();
  EXPECT_FALSE(db().in_transaction());
}

TEST_F(TransactionTest, ImmediateTakesTheWriteLockAtBegin) {
  auto other = tmp_.open_another();
  fail_fast(*other);
  Transaction tx(db(), Transaction::Mode::immediate);
  try {
    Transaction competing(*other, Transaction::Mode::immediate);
    FAIL() << "two writers at once";
  } catch (const DbError& e) {
    EXPECT_TRUE(is_busy(e)) << e.what();
  }
}

TEST_F(TransactionTest, DeferredTakesNoLockUntilItWrites) {
  auto other = tmp_.open_another();
  fail_fast(*other);
  Transaction tx(db(), Transaction::Mode::deferred);
  EXPECT_EQ(row_count(db(), "t"), 0);  // a read only
  Transaction competing(*other, Transaction::Mode::immediate);
  other->prepare("INSERT INTO t VALUES (7)").run();
  competing.commit();
}

// Inside another transaction a Transaction is a savepoint: committed, its changes wait for the
// outer commit (and an outer rollback undoes them); destroyed, it undoes only its own.
TEST_F(TransactionTest, NestedIsASavepointOfTheOuterTransaction) {
  {
    Transaction outer(db());
    insert(1);
    {
      Transaction inner(db());
      insert(2);
    }  // rolled back: 2 only
    EXPECT_TRUE(has(1));
    EXPECT_FALSE(has(2));
    {
      Transaction inner(db());
      insert(3);
      inner.commit();
    }
    EXPECT_TRUE(has(3));
    outer.commit();
  }
  EXPECT_TRUE(has(1));
  EXPECT_TRUE(has(3));
  {
    Transaction outer(db());
    {
      Transaction inner(db());
      insert(4);
      inner.commit();
    }
  }  // the outer rollback undoes the committed savepoint too
  EXPECT_FALSE(has(4));
  EXPECT_FALSE(db().in_transaction()) << "no transaction left open";
}

}  // namespace
}  // namespace incise::db
