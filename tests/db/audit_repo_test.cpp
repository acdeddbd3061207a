// Tests for db/audit_repo.h: an append-only log read back newest first, at most `limit` entries.
#include "db/audit_repo.h"

#include <gtest/gtest.h>

#include <string>

#include "temp_database.h"

namespace incise::db {
namespace {

class AuditRepoTest : public test::DbTest {
 protected:
  std::int64_t admin_ = test::add_user(db(), "admin", "admin");
  AuditRepo audit_{db()};
};

TEST_F(AuditRepoTest, RecordThenListNewestFirst) {
  audit_.record(admin_, "user.create", "bob", 100);
  audit_.record(std::nullopt, "server.start", "", 200);
  audit_.record(admin_, "station.create", "s1", 300);
  const auto all = audit_.list();
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[0].action, "station.create");
  EXPECT_EQ(all[0].at, 300);
  EXPECT_EQ(all[0].user_id, admin_);
  EXPECT_EQ(all[0].detail, "s1");
  EXPECT_EQ(all[1].action, "server.start");
  EXPECT_EQ(all[1].user_id, std::nullopt);
  EXPECT_EQ(all[2].action, "user.create");
  EXPECT_GT(all[0].id, all[1].id);
  EXPECT_GT(all[1].id, all[2].id);
}

TEST_F(AuditRepoTest, ListHonoursTheLimit) {
  for (int i = 0; i < 10; ++i) {
    std::string action = "a";
    action += std::to_string(i);
    audit_.record(admin_, action, "", 100 + i);
  }
  const auto last3 = audit_.list(3);
  ASSERT_EQ(last3.size(), 3u);
  EXPECT_EQ(last3[0].action, "a9");
  EXPECT_EQ(last3[1].action, "a8");
  EXPECT_EQ(last3[2].action, "a7");
  EXPECT_EQ(audit_.list(1).size(), 1u);
  EXPECT_EQ(audit_.list(100).size(), 10u);
  EXPECT_EQ(audit_.list().size(), 10u);
}

TEST_F(AuditRepoTest, EntryOfAnUnknownUserIsRefused) {
  EXPECT_THROW(audit_.record(admin_ + 100, "x", "", 1), ConstraintError);
  EXPECT_TRUE(audit_.list().empty());
}

}  // namespace
}  // namespace incise::db
