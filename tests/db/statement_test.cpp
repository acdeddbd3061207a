// Tests for db/statement.h: every bindable type comes back unchanged, and failures are typed.
#include "db/statement.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "db/database.h"
#include "db/db_error.h"
#include "temp_database.h"

namespace incise::db {
namespace {

// A column without type affinity stores exactly what was bound. SQLite's own behaviour (untyped
// columns, result codes): statement_engines_test.cpp holds what both engines must do.
class StatementTest : public ::testing::Test {
 protected:
  void SetUp() override { INCISE_SQLITE_ONLY(); }
  StatementTest() { db_.exec("CREATE TABLE v (x)"); }

  // Stores one value with `bind_value`, then reads it back from the table.
  template <class Bind>
  Statement round_trip(Bind bind_value) {
    db_.exec("DELETE FROM v");
    auto insert = db_.prepare("INSERT INTO v (x) VALUES (?)");
    bind_value(insert);
    insert.run();
    auto select = db_.prepare("SELECT x FROM v");
    EXPECT_TRUE(select.step());
    return select;
  }

  Database db_{":memory:"};
};

TEST_F(StatementTest, Int64ExtremesRoundTrip) {
  for (const std::int64_t value :
       {std::numeric_limits<std::int64_t>::min(), std::numeric_limits<std::int64_t>::max(),
        std::int64_t{-1}, std::int64_t{0}, (std::int64_t{1} << 53) | 1}) {
    auto q = round_trip([&](Statement& s) { s.bind(1, value); });
    EXPECT_EQ(q.int64(0), value);
    EXPECT_FALSE(q.is_null(0));
  }
}

TEST_F(StatementTest, IntBindsAsInteger) {
  auto q = round_trip([](Statement& s) { s.bind(1, -7); });
  EXPECT_EQ(q.int64(0), -7);
  auto type = db_.prepare("SELECT typeof(x) FROM v");
  type.step();
  EXPECT_EQ(type.text(0), "integer");
}

TEST_F(StatementTest, DoublesRoundTripBitExactly) {
  for (const double value :
       {0.1, -2.5e-300, std::numeric_limits<double>::max(),
        std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::infinity(),
        -std::numeric_limits<double>::infinity(), 1.0 / 3.0}) {
    auto q = round_trip([&](Statement& s) { s.bind(1, value); });
    EXPECT_EQ(q.real(0), value);
  }
}

TEST_F(StatementTest, Utf8TextWithEmbeddedNulRoundTrips) {
  const std::string text = std::string("Skalpell \xC3\xBC \xE2\x9C\x82 ") + '\0' + "after nul";
  ASSERT_EQ(text.size(), 26u);
  auto q = round_trip([&](Statement& s) { s.bind(1, text); });
  EXPECT_EQ(q.text(0), text);
  auto length = db_.prepare("SELECT length(CAST(x AS BLOB)) FROM v");
  length.step();
  EXPECT_EQ(length.int64(0), static_cast<std::int64_t>(text.size()));
}

TEST_F(StatementTest, CStringAndEmptyTextBindAsText) {
  auto q = round_trip([](Statement& s) { s.bind(1, "plain"); });
  EXPECT_EQ(q.text(0), "plain");
  auto empty = round_trip([](Statement& s) { s.bind(1, std::string()); });
  EXPECT_FALSE(empty.is_null(0));
  EXPECT_EQ(empty.text(0), "");
}

// A default-constructed string_view has data() == nullptr; it is still empty text, not NULL.
TEST_F(StatementTest, DefaultStringViewIsEmptyTextNotNull) {
  auto q = round_trip([](Statement& s) { s.bind(1, std::string_view()); });
  EXPECT_FALSE(q.is_null(0));
  EXPECT_EQ(q.text(0), "");
}

TEST_F(StatementTest, BlobWithEveryByteValueRoundTrips) {
  std::vector<std::uint8_t> bytes;
  for (int i = 0; i < 512; ++i)
    bytes.push_back(static_cast<std::uint8_t>(i * 7));
  auto q = round_trip([&](Statement& s) { s.bind_blob(1, bytes); });
  EXPECT_EQ(q.blob(0), bytes);
}

// An empty blob is a value, not NULL (recording_chunks.data is NOT NULL, for instance).
TEST_F(StatementTest, EmptyBlobIsNotNull) {
  auto q = round_trip([](Statement& s) { s.bind_blob(1, {}); });
  EXPECT_FALSE(q.is_null(0));
  EXPECT_TRUE(q.blob(0).empty());
}

TEST_F(StatementTest, NullRoundTrips) {
  auto q = round_trip([](Statement& s) { s.bind_null(1); });
  EXPECT_TRUE(q.is_null(0));
  EXPECT_EQ(q.optional_int64(0), std::nullopt);
  EXPECT_EQ(q.text(0), "");
  EXPECT_TRUE(q.blob(0).empty());
}

TEST_F(StatementTest, OptionalBindsValueOrNull) {
  auto some = round_trip([](Statement& s) { s.bind(1, std::optional<std::int64_t>(5)); });
  EXPECT_EQ(some.optional_int64(0), 5);
  auto none = round_trip([](Statement& s) { s.bind(1, std::optional<std::int64_t>()); });
  EXPECT_TRUE(none.is_null(0));
  EXPECT_EQ(none.optional_int64(0), std::nullopt);
}

TEST_F(StatementTest, StepWalksEveryRowInOrder) {
  db_.exec("INSERT INTO v VALUES (1), (2), (3)");
  auto q = db_.prepare("SELECT x FROM v ORDER BY x");
  std::vector<std::int64_t> seen;
  while (q.step())
    seen.push_back(q.int64(0));
  EXPECT_EQ(seen, (std::vector<std::int64_t>{1, 2, 3}));
}

TEST_F(StatementTest, ResetClearsBindingsAndAllowsReuse) {
  auto insert = db_.prepare("INSERT INTO v (x) VALUES (?)");
  insert.bind(1, 1).run();
  insert.reset();
  insert.run();  // the binding was cleared: inserts NULL
  auto q = db_.prepare("SELECT COUNT(*), COUNT(x) FROM v");
  q.step();
  EXPECT_EQ(q.int64(0), 2);
  EXPECT_EQ(q.int64(1), 1);
}

TEST_F(StatementTest, MovedStatementStillWorks) {
  auto a = db_.prepare("SELECT 42");
  Statement b(std::move(a));
  ASSERT_TRUE(b.step());
  EXPECT_EQ(b.int64(0), 42);
}

TEST_F(StatementTest, BadSqlThrowsAtPrepare) {
  EXPECT_THROW(db_.prepare("SELEC 1"), DbError);
  EXPECT_THROW(db_.prepare("SELECT * FROM no_such_table"), DbError);
}

TEST_F(StatementTest, BindingAnOutOfRangeIndexThrows) {
  auto q = db_.prepare("SELECT ?");
  try {
    q.bind(2, 1);
    FAIL();
  } catch (const DbError& e) {
    EXPECT_EQ(e.code(), SQLITE_RANGE);
  }
}

TEST_F(StatementTest, EveryConstraintViolationThrowsConstraintError) {
  db_.exec(
      "CREATE TABLE p (id INTEGER PRIMARY KEY);"
      "CREATE TABLE c (u UNIQUE, n NOT NULL DEFAULT 0, k CHECK (k > 0), p REFERENCES p (id));"
      "INSERT INTO p VALUES (1); INSERT INTO c (u, k, p) VALUES (1, 1, 1);");
  const struct {
    const char* sql;
    int code;
  } cases[] = {
      {"INSERT INTO c (u, k) VALUES (1, 1)", SQLITE_CONSTRAINT_UNIQUE},
      {"INSERT INTO c (u, n, k) VALUES (2, NULL, 1)", SQLITE_CONSTRAINT_NOTNULL},
      {"INSERT INTO c (u, k) VALUES (3, 0)", SQLITE_CONSTRAINT_CHECK},
      {"INSERT INTO c (u, k, p) VALUES (4, 1, 99)", SQLITE_CONSTRAINT_FOREIGNKEY},
  };
  for (const auto& c : cases) {
    auto q = db_.prepare(c.sql);
    try {
      q.run();
      ADD_FAILURE() << "accepted: " << c.sql;
    } catch (const ConstraintError& e) {
      EXPECT_EQ(e.code(), c.code) << c.sql;
    }
  }
  auto count = db_.prepare("SELECT COUNT(*) FROM c");
  count.step();
  EXPECT_EQ(count.int64(0), 1) << "no refused row was stored";
}

TEST_F(StatementTest, OtherStepErrorsAreDbErrorNotConstraintError) {
  // Integer overflow in abs() is a runtime error, not a constraint.
  auto q = db_.prepare("SELECT abs(-9223372036854775807 - 1)");
  try {
    q.step();
    FAIL();
  } catch (const ConstraintError&) {
    FAIL() << "not a constraint violation";
  } catch (const DbError& e) {
    EXPECT_NE(std::string(e.what()).find("integer overflow"), std::string::npos) << e.what();
  }
}

TEST_F(StatementTest, FailedStepCanBeRetried) {
  db_.exec("CREATE TABLE u (x UNIQUE); INSERT INTO u VALUES (1)");
  auto insert = db_.prepare("INSERT INTO u VALUES (?)");
  insert.bind(1, 1);
  EXPECT_THROW(insert.run(), ConstraintError);
  insert.bind(1, 2);
  EXPECT_NO_THROW(insert.run());
  auto q = db_.prepare("SELECT COUNT(*) FROM u");
  q.step();
  EXPECT_EQ(q.int64(0), 2);
}

}  // namespace
}  // namespace incise::db
