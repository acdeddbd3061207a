// Tests for db/stations_repo.h: a station is found by its agent's token and by nothing else.
#include "db/stations_repo.h"

#include <gtest/gtest.h>

#include <string>

#include "db/password.h"
#include "db/statement.h"
#include "temp_database.h"

namespace incise::db {
namespace {

using test::DbTest;
using test::row_count;

class StationsRepoTest : public DbTest {
 protected:
  StationsRepo stations_{db()};
};

TEST_F(StationsRepoTest, CreateThenFind) {
  const Station created = stations_.create("Station 1", "Room 2.14", random_token(), 500);
  EXPECT_GT(created.id, 0);
  EXPECT_EQ(created.name, "Station 1");
  EXPECT_EQ(created.location, "Room 2.14");
  EXPECT_EQ(created.created_at, 500);
  const auto found = stations_.find(created.id);
  ASSERT_TRUE(found);
  EXPECT_EQ(found->id, created.id);
  EXPECT_EQ(found->name, "Station 1");
  EXPECT_EQ(found->location, "Room 2.14");
  EXPECT_EQ(found->created_at, 500);
  EXPECT_FALSE(stations_.find(created.id + 1));
}

TEST_F(StationsRepoTest, AStationDeclaresItsKindAndAnAdminMayChangeIt) {
  const Station plain = stations_.create("Station 1", "", random_token(), 500);
  EXPECT_EQ(plain.kind, "");
  const Station lap = stations_.create("Surgical", "", random_token(), 500, "laparoscopy");
  EXPECT_EQ(lap.kind, "laparoscopy");
  EXPECT_EQ(stations_.find(lap.id)->kind, "laparoscopy");
  stations_.set_kind(plain.id, "bench");
  EXPECT_EQ(stations_.find(plain.id)->kind, "bench");
  EXPECT_EQ(stations_.list().front().kind, "bench");
  EXPECT_THROW(stations_.set_kind(lap.id + 100, "bench"), NotFound);
}

TEST_F(StationsRepoTest, FindByTokenAcceptsOnlyTheRightToken) {
  const std::string token_a = random_token();
  const std::string token_b = random_token();
  const Station a = stations_.create("A", "", token_a, 1);
  const Station b = stations_.create("B", "", token_b, 1);
  const auto found_a = stations_.find_by_token(token_a);
  const auto found_b = stations_.find_by_token(token_b);
  ASSERT_TRUE(found_a);
  ASSERT_TRUE(found_b);
  EXPECT_EQ(found_a->id, a.id);
  EXPECT_EQ(found_b->id, b.id);
  EXPECT_FALSE(stations_.find_by_token(random_token()));
  EXPECT_FALSE(stations_.find_by_token(""));
  std::string almost = token_a;
  almost.back() = almost.back() == 'f' ? 'e' : 'f';
  EXPECT_FALSE(stations_.find_by_token(almost));
}

TEST_F(StationsRepoTest, OnlyTheTokensHashIsStored) {
  const std::string token = random_token();
  stations_.create("A", "", token, 1);
  const bool sqlite = db().dialect() == Dialect::sqlite;
  auto q = db().prepare(sqlite ? "SELECT token_hash, typeof(token_hash) FROM stations"
                               : "SELECT token_hash, pg_typeof(token_hash)::text FROM stations");
  ASSERT_TRUE(q.step());
  EXPECT_EQ(q.blob(0), token_hash(token));
  EXPECT_EQ(q.text(1), sqlite ? "blob" : "bytea");
}

TEST_F(StationsRepoTest, DuplicateNameThrowsConflictAndChangesNothing) {
  const std::string token = random_token();
  stations_.create("A", "first", token, 1);
  EXPECT_THROW(stations_.create("A", "second", random_token(), 2), Conflict);
  EXPECT_EQ(row_count(db(), "stations"), 1);
  const auto found = stations_.find_by_token(token);
  ASSERT_TRUE(found);
  EXPECT_EQ(found->location, "first");
}

TEST_F(StationsRepoTest, ListIsOrderedByName) {
  for (const char* name : {"C", "A", "B"})
    stations_.create(name, "", random_token(), 1);
  const auto all = stations_.list();
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[0].name, "A");
  EXPECT_EQ(all[1].name, "B");
  EXPECT_EQ(all[2].name, "C");
}

// A default-constructed string_view (data() == nullptr) is an empty location, not NULL.
TEST_F(StationsRepoTest, EmptyStringViewLocationIsStoredAsEmpty) {
  const Station s = stations_.create("A", std::string_view(), random_token(), 1);
  const auto found = stations_.find(s.id);
  ASSERT_TRUE(found);
  EXPECT_EQ(found->location, "");
}

}  // namespace
}  // namespace incise::db
