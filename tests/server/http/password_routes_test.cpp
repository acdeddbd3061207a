// Which requests check or hash a password, and so run on the password workers rather than an I/O
// thread (server/http/http_session.h: checks_password); and ApiContext::hash_password, which makes
// the hash without the database lock and takes the lock back.
#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <string>
#include <thread>

#include "db/password.h"
#include "server/api/api_context.h"
#include "server/http/http_session.h"
#include "tests/server/api/api_test_app.h"

namespace incise::server::test {
namespace {

Request request(http::verb method, const std::string& target) {
  Request r{method, target, 11};
  r.set(http::field::host, "localhost");
  return r;
}

TEST(PasswordRoutes, EveryRequestThatHashesOrChecksAPasswordRunsOnTheWorkers) {
  for (const char* target :
       {"/api/login", "/api/me/password", "/api/users", "/api/users/7/password",
        "/api/users/12/password?x=1", "/api/login?next=/"}) {
    EXPECT_TRUE(checks_password(request(http::verb::post, target))) << target;
    EXPECT_FALSE(checks_password(request(http::verb::get, target))) << target;
  }
  for (const char* target :
       {"/api/users/7", "/api/users//password", "/api/users/7/8/password", "/api/me",
        "/api/users/password", "/api/usersx", "/api/login/x", "/api/users/7/passwordx"}) {
    EXPECT_FALSE(checks_password(request(http::verb::post, target))) << target;
  }
}

class HashPassword : public ApiTest {};

// The lock is free while the hash is made: another thread waiting for it gets it then (it cannot
// once hash_password has taken it back and until the test lets it go).
TEST_F(HashPassword, GivesAHashThatVerifiesAndTakesTheLockBack) {
  std::mutex mutex;
  std::unique_lock lock(mutex);
  std::atomic<bool> waiting = false, got = false;
  std::thread other([&] {
    waiting = true;
    const std::lock_guard taken(mutex);
    got = true;
  });
  while (!waiting)
    std::this_thread::yield();
  const Request r = request(http::verb::post, "/api/users");
  ApiContext ctx(r, app(), Caller{"127.0.0.1", false});
  ctx.db_lock = &lock;
  const db::PasswordHash hash = ctx.hash_password("correct horse battery");
  EXPECT_TRUE(lock.owns_lock());
  EXPECT_TRUE(got) << "the lock was held through the hash";
  lock.unlock();
  other.join();
  EXPECT_TRUE(db::verify_password("correct horse battery", hash.value));
  EXPECT_FALSE(db::verify_password("correct horse battery!", hash.value));
}

}  // namespace
}  // namespace incise::server::test
