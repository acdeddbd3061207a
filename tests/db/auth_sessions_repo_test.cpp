// Tests for db/auth_sessions_repo.h. Times are explicit `now` values; a session expiring at T is
// valid for now < T.
#include "db/auth_sessions_repo.h"

#include <gtest/gtest.h>

#include <atomic>
#include <string>
#include <thread>
#include <vector>

#include "db/password.h"
#include "db/statement.h"
#include "temp_database.h"

namespace incise::db {
namespace {

using test::DbTest;
using test::row_count;

class AuthSessionsRepoTest : public DbTest {
 protected:
  std::int64_t expiry_of(const std::string& token) {
    auto q = db().prepare("SELECT expires_at FROM auth_sessions WHERE token_hash = ?");
    q.bind_blob(1, token_hash(token));
    EXPECT_TRUE(q.step()) << "no session row for the token";
    return q.int64(0);
  }

  std::int64_t ann_ = test::add_user(db(), "ann", "instructor");
  AuthSessionsRepo sessions_{db()};
};

TEST_F(AuthSessionsRepoTest, TokenWorksUntilExpiryAndNotAfter) {
  const std::string token = sessions_.create(ann_, 1000, 100);
  EXPECT_EQ(token.size(), 64u);
  EXPECT_EQ(expiry_of(token), 1100);
  // Touching at 1099 with a ttl of 1 leaves the expiry where it was.
  const auto user = sessions_.touch(token, 1099, 1);
  ASSERT_TRUE(user);
  EXPECT_EQ(user->id, ann_);
  EXPECT_EQ(user->username, "ann");
  EXPECT_EQ(user->role, Role::instructor);
  EXPECT_EQ(expiry_of(token), 1100);
  EXPECT_FALSE(sessions_.touch(token, 1100, 100)) << "still valid at its expiry instant";
  EXPECT_FALSE(sessions_.touch(token, 5000, 100));
  EXPECT_EQ(expiry_of(token), 1100) << "an expired session was revived";
}

TEST_F(AuthSessionsRepoTest, TouchSlidesTheExpiry) {
  const std::string token = sessions_.create(ann_, 1000, 100);
  ASSERT_TRUE(sessions_.touch(token, 1090, 100));
  EXPECT_EQ(expiry_of(token), 1190);
  EXPECT_TRUE(sessions_.touch(token, 1150, 100)) << "would have expired at 1100 without sliding";
  EXPECT_TRUE(sessions_.touch(token, 1240, 100));
  EXPECT_FALSE(sessions_.touch(token, 1340, 100));
}

// A request a moment after the last one only reads: the expiry moves when it would move by more
// than a hundredth of the lifetime.
TEST_F(AuthSessionsRepoTest, TouchWritesOnlyWhenTheExpiryMovesByAHundredthOfTheLifetime) {
  const std::string token = sessions_.create(ann_, 1000, 10'000);  // expires 11000
  ASSERT_TRUE(sessions_.touch(token, 1100, 10'000));
  EXPECT_EQ(expiry_of(token), 11000) << "moved by 100 s, no more than a hundredth";
  ASSERT_TRUE(sessions_.touch(token, 1101, 10'000));
  EXPECT_EQ(expiry_of(token), 11101);
}

TEST_F(AuthSessionsRepoTest, UnknownTokenIsRejected) {
  sessions_.create(ann_, 1000, 100);
  EXPECT_FALSE(sessions_.touch(random_token(), 1001, 100));
  EXPECT_FALSE(sessions_.touch("", 1001, 100));
}

TEST_F(AuthSessionsRepoTest, RemoveEndsOnlyThatSession) {
  const std::string a = sessions_.create(ann_, 1000, 100);
  const std::string b = sessions_.create(ann_, 1000, 100);
  EXPECT_NE(a, b);
  sessions_.remove(a);
  EXPECT_FALSE(sessions_.touch(a, 1001, 100));
  EXPECT_TRUE(sessions_.touch(b, 1001, 100));
  sessions_.remove(a);  // removing twice is harmless
  EXPECT_EQ(row_count(db(), "auth_sessions"), 1);
}

TEST_F(AuthSessionsRepoTest, PurgeExpiredDeletesOnlyExpired) {
  const std::string old1 = sessions_.create(ann_, 0, 100);     // expires 100
  const std::string old2 = sessions_.create(ann_, 50, 150);    // expires 200
  const std::string live1 = sessions_.create(ann_, 100, 101);  // expires 201
  const std::string live2 = sessions_.create(ann_, 150, 1000);
  EXPECT_EQ(sessions_.purge_expired(200), 2);
  EXPECT_EQ(row_count(db(), "auth_sessions"), 2);
  EXPECT_TRUE(sessions_.touch(live1, 200, 1));
  EXPECT_TRUE(sessions_.touch(live2, 200, 1));
  EXPECT_EQ(sessions_.purge_expired(200), 0);
  // Purge and touch agree on the boundary: what touch refuses, purge deletes.
  EXPECT_EQ(sessions_.purge_expired(201), 2);
}

TEST_F(AuthSessionsRepoTest, OnlyAHashOfTheTokenIsStored) {
  const std::string token = sessions_.create(ann_, 1000, 100);
  auto q = db().prepare("SELECT * FROM auth_sessions");
  ASSERT_TRUE(q.step());
  for (int column = 0; column < 4; ++column) {
    EXPECT_EQ(q.text(column).find(token), std::string::npos) << "column " << column;
    const auto bytes = q.blob(column);
    EXPECT_EQ(std::string(bytes.begin(), bytes.end()).find(token), std::string::npos);
  }
  auto hash = db().prepare("SELECT token_hash FROM auth_sessions");
  ASSERT_TRUE(hash.step());
  EXPECT_EQ(hash.blob(0), token_hash(token));
}

TEST_F(AuthSessionsRepoTest, SessionOfAnUnknownUserIsRefused) {
  EXPECT_THROW(sessions_.create(ann_ + 100, 1000, 100), ConstraintError);
  EXPECT_EQ(row_count(db(), "auth_sessions"), 0);
}

// A request checks its cookie (touch) while a live session's own connection writes to the same
// file. Touch must never fail with "database is locked": its write has to wait on the busy timeout,
// which SQLite does not do when a read transaction is upgraded after another connection committed.
TEST_F(AuthSessionsRepoTest, TouchSurvivesAnotherConnectionWriting) {
  const std::string token = sessions_.create(ann_, 1000, 1'000'000);
  auto other = tmp_.open_another();
  std::atomic<bool> done = false;
  std::thread writer([&] {
    for (std::int64_t i = 0; !done; ++i) {
      other->prepare("UPDATE users SET created_at = ? WHERE id = ?").bind(1, i).bind(2, ann_).run();
    }
  });
  int touched = 0;
  try {
    for (; touched < 2000; ++touched)
      ASSERT_TRUE(sessions_.touch(token, 1001 + touched, 99));  // under 100 s: every touch writes
  } catch (const DbError& e) {
    ADD_FAILURE() << "touch " << touched << " failed: " << e.what();
  }
  done = true;
  writer.join();
  EXPECT_EQ(touched, 2000);
  EXPECT_EQ(expiry_of(token), 1000 + 2000 + 99);
}

}  // namespace
}  // namespace incise::db
