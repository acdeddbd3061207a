// Password-guessing limits: server/login_limiter.h (the policy is in docs/security.md, "Logins").
#include "server/login_limiter.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

namespace incise::server {
namespace {

constexpr std::int64_t kT0 = 1894003200;
const std::string kHere = "192.0.2.7";
const LoginPolicy kPolicy;

// `n` failures at `account` from `address`, each as soon as the limiter allows it; returns the
// time after the last one.
std::int64_t fail(LoginLimiter& limiter, const std::string& account, const std::string& address,
                  int n, std::int64_t t) {
  for (int i = 0; i < n; ++i) {
    t += limiter.retry_after(account, address, t);
    limiter.record_failure(account, address, t);
  }
  return t;
}

TEST(LoginLimiter, AFewFailuresCostNothingThenTheWaitDoubles) {
  LoginLimiter limiter;
  std::int64_t t = kT0;
  for (int i = 0; i < kPolicy.free_per_pair; ++i) {
    ASSERT_EQ(limiter.retry_after("admin", kHere, t), 0) << i;
    limiter.record_failure("admin", kHere, t);
  }
  // The free ones are spent: 1 s, then 2, 4, 8 ... after each further failure.
  EXPECT_EQ(limiter.retry_after("admin", kHere, t), 0);
  limiter.record_failure("admin", kHere, t);
  for (std::int64_t expected = 1; expected <= 256; expected *= 2) {
    EXPECT_EQ(limiter.retry_after("admin", kHere, t), expected);
    t += expected;
    EXPECT_EQ(limiter.retry_after("admin", kHere, t), 0);
    limiter.record_failure("admin", kHere, t);
  }
}

TEST(LoginLimiter, TheWaitHasACeiling) {
  LoginLimiter limiter;
  const auto t = fail(limiter, "admin", kHere, 40, kT0);
  EXPECT_EQ(limiter.retry_after("admin", kHere, t), kPolicy.max_wait_s);
}

TEST(LoginLimiter, CountsAreForgottenAfterQuiet) {
  LoginLimiter limiter;
  const auto t = fail(limiter, "admin", kHere, 12, kT0);
  EXPECT_GT(limiter.retry_after("admin", kHere, t), 0);
  const auto later = t + kPolicy.forget_after_s;
  EXPECT_EQ(limiter.retry_after("admin", kHere, later), 0);
  // A fresh count: the free failures are free again.
  fail(limiter, "admin", kHere, kPolicy.free_per_pair, later);
  EXPECT_EQ(limiter.retry_after("admin", kHere, later), 0);
}

// The attack: nine guesses at admin, one login to one's own account, again and again.
TEST(LoginLimiter, LoggingIntoOnesOwnAccountBuysNoGuessesAtAnother) {
  LoginLimiter limiter;
  std::int64_t t = kT0;
  int free_guesses = 0;
  for (int round = 0; round < 5; ++round) {
    for (int i = 0; i < 9; ++i) {
      if (limiter.retry_after("admin", kHere, t) == 0) ++free_guesses;
      t += limiter.retry_after("admin", kHere, t);
      limiter.record_failure("admin", kHere, t);
    }
    ASSERT_EQ(limiter.retry_after("mallory", kHere, t), 0) << "their own account is not held";
    limiter.record_success("mallory", kHere, t);
  }
  EXPECT_EQ(free_guesses, kPolicy.free_per_pair + 1);
  EXPECT_GE(limiter.retry_after("admin", kHere, t), 256);
}

TEST(LoginLimiter, ManyAddressesShareTheAccountsLimit) {
  LoginLimiter limiter;
  // Ten addresses, each within its own pair's free failures: 10 x 4 = 40 guesses at admin.
  for (int a = 0; a < 10; ++a)
    fail(limiter, "admin", "198.51.100." + std::to_string(a), kPolicy.free_per_pair - 1, kT0);
  // The account's count is past its free ones: a new address waits too.
  EXPECT_GT(limiter.retry_after("admin", "203.0.113.9", kT0), 0);
}

TEST(LoginLimiter, OneAddressGuessingManyAccountsIsHeldBack) {
  LoginLimiter limiter;
  for (int a = 0; a < kPolicy.free_per_address + 1; ++a)
    limiter.record_failure("user" + std::to_string(a), kHere, kT0);
  EXPECT_GT(limiter.retry_after("someone-else", kHere, kT0), 0);
  EXPECT_EQ(limiter.retry_after("someone-else", "192.0.2.8", kT0), 0);
}

TEST(LoginLimiter, TheRealUserIsNotLockedOutByOthersGuesses) {
  LoginLimiter limiter;
  const std::string office = "192.0.2.50";
  limiter.record_success("admin", office, kT0);  // admin logged in from the office before
  // Guesses at admin from everywhere, and from the office's shared address at other accounts.
  for (int a = 0; a < 30; ++a)
    fail(limiter, "admin", "198.51.100." + std::to_string(a), 4, kT0 + 60);
  for (int a = 0; a < 30; ++a)
    limiter.record_failure("user" + std::to_string(a), office, kT0 + 60);
  EXPECT_GT(limiter.retry_after("admin", "203.0.113.9", kT0 + 60), 0) << "an unknown address";
  EXPECT_EQ(limiter.retry_after("admin", office, kT0 + 60), 0) << "the known address";
  // The real user's own mistypes are counted for them only.
  fail(limiter, "admin", office, kPolicy.free_per_pair + 3, kT0 + 60);
  EXPECT_GT(limiter.retry_after("admin", office, kT0 + 60), 0);
}

TEST(LoginLimiter, ASuccessClearsOnlyItsOwnAccountAtItsOwnAddress) {
  LoginLimiter limiter;
  const auto t = fail(limiter, "ann", kHere, 8, kT0);
  const auto t2 = fail(limiter, "ann", "192.0.2.8", 8, kT0);
  ASSERT_GT(limiter.retry_after("ann", kHere, t), 0);
  limiter.record_success("ann", kHere, t + limiter.retry_after("ann", kHere, t));
  EXPECT_EQ(limiter.retry_after("ann", kHere, t + 300), 0);
  EXPECT_GT(limiter.retry_after("ann", "192.0.2.8", t2), 0);
}

TEST(LoginLimiter, TheCaseOfAUsernameMakesNoFreshCount) {
  LoginLimiter limiter;
  const auto t = fail(limiter, "admin", kHere, 8, kT0);
  EXPECT_EQ(limiter.retry_after("ADMIN", kHere, t), limiter.retry_after("admin", kHere, t));
}

TEST(LoginLimiter, MemoryIsBoundedUnderAFloodOfNames) {
  LoginPolicy policy;
  policy.max_entries = 100;
  LoginLimiter limiter(policy);
  for (int a = 0; a < 1000; ++a)
    limiter.record_failure("user" + std::to_string(a), "198.51.100." + std::to_string(a % 250),
                           kT0 + a);
  // The newest entries are kept: the last address's count is still there.
  fail(limiter, "user999", "198.51.100.249", kPolicy.free_per_pair, kT0 + 1000);
  EXPECT_GT(limiter.retry_after("user999", "198.51.100.249", kT0 + 1000), 0);
}

}  // namespace
}  // namespace incise::server
