// Tests for db/users_repo.h. Every create hashes a password (~0.1 s), so users are few.
#include "db/users_repo.h"

#include <gtest/gtest.h>

#include <string>

#include "db/password.h"
#include "db/statement.h"
#include "temp_database.h"

namespace incise::db {
namespace {

using test::DbTest;

class UsersRepoTest : public DbTest {
 protected:
  UsersRepo users_{db()};
};

std::string stored_hash(Database& db, std::int64_t id) {
  auto q = db.prepare("SELECT password_hash FROM users WHERE id = ?");
  q.bind(1, id);
  EXPECT_TRUE(q.step());
  return q.text(0);
}

TEST(Role, RoundTripsThroughText) {
  for (const Role role : {Role::trainee, Role::instructor, Role::admin})
    EXPECT_EQ(parse_role(to_string(role)), role) << to_string(role);
  EXPECT_EQ(to_string(Role::trainee), "trainee");
  EXPECT_EQ(to_string(Role::instructor), "instructor");
  EXPECT_EQ(to_string(Role::admin), "admin");
}

TEST(Role, ParseRejectsUnknownText) {
  for (const char* text : {"", "root", "Admin", "admin ", "trainees"})
    EXPECT_EQ(parse_role(text), std::nullopt) << '"' << text << '"';
}

TEST_F(UsersRepoTest, CreateThenFindByIdAndUsername) {
  const User created = users_.create({"ann", "Ann Smith", Role::instructor, "pw-ann"}, 1000);
  EXPECT_GT(created.id, 0);
  EXPECT_EQ(created.username, "ann");
  EXPECT_EQ(created.display_name, "Ann Smith");
  EXPECT_EQ(created.role, Role::instructor);
  EXPECT_EQ(created.created_at, 1000);

  for (const auto& found : {users_.find(created.id), users_.find_by_username("ann")}) {
    ASSERT_TRUE(found);
    EXPECT_EQ(found->id, created.id);
    EXPECT_EQ(found->username, "ann");
    EXPECT_EQ(found->display_name, "Ann Smith");
    EXPECT_EQ(found->role, Role::instructor);
    EXPECT_EQ(found->created_at, 1000);
  }
  EXPECT_FALSE(users_.find(created.id + 1));
  EXPECT_FALSE(users_.find_by_username("Ann"));
  EXPECT_FALSE(users_.find_by_username("nobody"));
}

TEST_F(UsersRepoTest, EveryRoleIsStoredAndReadBack) {
  // Seeded without hashing: the role column is what is under test.
  for (const Role role : {Role::trainee, Role::instructor, Role::admin}) {
    const std::string name = "u-" + std::string(to_string(role));
    test::add_user(db(), name, to_string(role));
    const auto found = users_.find_by_username(name);
    ASSERT_TRUE(found);
    EXPECT_EQ(found->role, role);
  }
}

TEST_F(UsersRepoTest, ListIsOrderedByUsernameAndCountMatches) {
  EXPECT_EQ(users_.count(), 0);
  EXPECT_TRUE(users_.list().empty());
  for (const char* name : {"carl", "ann", "bob"})
    test::add_user(db(), name);
  const auto all = users_.list();
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[0].username, "ann");
  EXPECT_EQ(all[1].username, "bob");
  EXPECT_EQ(all[2].username, "carl");
  EXPECT_EQ(users_.count(), 3);
}

TEST_F(UsersRepoTest, DuplicateUsernameThrowsConflictAndChangesNothing) {
  const User ann = users_.create({"ann", "Ann", Role::trainee, "first"}, 1);
  EXPECT_THROW(users_.create({"ann", "Other Ann", Role::admin, "second"}, 2), Conflict);
  EXPECT_EQ(users_.count(), 1);
  const auto found = users_.find_by_username("ann");
  ASSERT_TRUE(found);
  EXPECT_EQ(found->id, ann.id);
  EXPECT_EQ(found->display_name, "Ann");
  EXPECT_EQ(found->role, Role::trainee);
  EXPECT_TRUE(verify_password("first", stored_hash(db(), ann.id)));
}

TEST_F(UsersRepoTest, StoresAnArgon2idHashNeverThePassword) {
  const User ann = users_.create({"ann", "Ann", Role::trainee, "s3cret-pw"}, 1);
  const std::string hash = stored_hash(db(), ann.id);
  EXPECT_NE(hash, "s3cret-pw");
  EXPECT_EQ(hash.find("s3cret-pw"), std::string::npos);
  EXPECT_EQ(hash.rfind("$argon2id$", 0), 0u) << hash;
  EXPECT_TRUE(verify_password("s3cret-pw", hash));
}

TEST_F(UsersRepoTest, AuthenticateRightWrongAndUnknown) {
  const User ann = users_.create({"ann", "Ann", Role::admin, "right"}, 1);
  const auto ok = users_.authenticate("ann", "right");
  ASSERT_TRUE(ok);
  EXPECT_EQ(ok->id, ann.id);
  EXPECT_EQ(ok->role, Role::admin);
  EXPECT_FALSE(users_.authenticate("ann", "wrong"));
  EXPECT_FALSE(users_.authenticate("ann", ""));
  EXPECT_FALSE(users_.authenticate("nobody", "right"));
  EXPECT_FALSE(users_.authenticate("Ann", "right")) << "usernames are case-sensitive";
}

TEST_F(UsersRepoTest, SeededPlaceholderHashNeverAuthenticates) {
  test::add_user(db(), "seeded");
  EXPECT_FALSE(users_.authenticate("seeded", "not-a-hash"));
  EXPECT_FALSE(users_.authenticate("seeded", ""));
}

}  // namespace
}  // namespace incise::db
