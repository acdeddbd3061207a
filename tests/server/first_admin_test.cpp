// A real site's first admin from INCISE_ADMIN_PASSWORD (server/first_admin.h), on a real SQLite
// file: created once on an empty database, with a password to replace at the first login.
#include "server/first_admin.h"

#include <gtest/gtest.h>

#include "db/migrations.h"
#include "db/password.h"
#include "db/users_repo.h"
#include "tests/support/temp_dir.h"

namespace incise::server {
namespace {

class FirstAdminTest : public ::testing::Test {
 protected:
  FirstAdminTest() { db::apply_migrations(db_); }
  incise::test::TempDir dir_{"incise-first-admin"};
  db::Database db_{db::DatabaseUrl::sqlite(dir_.path() / "incise.db")};
};

TEST_F(FirstAdminTest, AnEmptyDatabaseGetsAnAdminWhoMustChooseAnotherPassword) {
  const auto first = create_first_admin(db_, "a long first password 1", 100);
  EXPECT_TRUE(first.created);
  EXPECT_EQ(first.problem, "");
  db::UsersRepo users(db_);
  const auto admin = users.authenticate("admin", "a long first password 1");
  ASSERT_TRUE(admin);
  EXPECT_EQ(admin->role, db::Role::admin);
  EXPECT_TRUE(admin->must_change_password);
  EXPECT_EQ(users.count(), 1);
}

TEST_F(FirstAdminTest, WithUsersPresentNothingChanges) {
  ASSERT_TRUE(create_first_admin(db_, "a long first password 1", 100).created);
  db::UsersRepo users(db_);
  const auto id = users.find_by_username("admin")->id;
  users.set_password(id, "the admin's own choice 2", false);
  // The variable stays set in the deployment; every later start leaves the admin alone.
  const auto again = create_first_admin(db_, "another password here 3", 200);
  EXPECT_FALSE(again.created);
  EXPECT_EQ(again.problem, "");
  EXPECT_TRUE(users.authenticate("admin", "the admin's own choice 2"));
  EXPECT_FALSE(users.find(id)->must_change_password);
  EXPECT_EQ(users.count(), 1);
}

TEST_F(FirstAdminTest, AWeakPasswordIsRefusedAndNothingIsCreated) {
  const auto weak = create_first_admin(db_, "admin", 100);
  EXPECT_FALSE(weak.created);
  EXPECT_EQ(weak.problem, "INCISE_ADMIN_PASSWORD: " + db::password_problem("admin", "admin"));
  EXPECT_NE(db::password_problem("admin", "admin"), "");
  EXPECT_EQ(db::UsersRepo(db_).count(), 0);
}

}  // namespace
}  // namespace incise::server
