// Tests for db/curricula_repo.h: definitions are stored verbatim under a unique name.
#include "db/curricula_repo.h"

#include <gtest/gtest.h>

#include <string>

#include "temp_database.h"

namespace incise::db {
namespace {

class CurriculaRepoTest : public test::DbTest {
 protected:
  CurriculaRepo curricula_{db()};
};

TEST_F(CurriculaRepoTest, CreateThenListByName) {
  const std::string json = R"({"name":"basics","modules":[{"task":"incision","pass":0.8}]})";
  const auto b = curricula_.create("basics", json, 100);
  const auto a = curricula_.create("advanced", "{}", 200);
  EXPECT_GT(b.id, 0);
  EXPECT_NE(a.id, b.id);
  EXPECT_EQ(b.name, "basics");
  EXPECT_EQ(b.definition_json, json);
  EXPECT_EQ(b.created_at, 100);
  const auto all = curricula_.list();
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].id, a.id);
  EXPECT_EQ(all[0].name, "advanced");
  EXPECT_EQ(all[1].id, b.id);
  EXPECT_EQ(all[1].definition_json, json);
  EXPECT_EQ(all[1].created_at, 100);
}

TEST_F(CurriculaRepoTest, DuplicateNameThrowsConflictAndKeepsTheOriginal) {
  curricula_.create("basics", R"({"v":1})", 1);
  EXPECT_THROW(curricula_.create("basics", R"({"v":2})", 2), Conflict);
  const auto all = curricula_.list();
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].definition_json, R"({"v":1})");
}

TEST_F(CurriculaRepoTest, EmptyListWhenNone) {
  EXPECT_TRUE(curricula_.list().empty());
}

}  // namespace
}  // namespace incise::db
