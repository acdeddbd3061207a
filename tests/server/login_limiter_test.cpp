// Failed-login limits per address: server/login_limiter.h.
#include "server/login_limiter.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

namespace incise::server {
namespace {

constexpr std::int64_t kT0 = 1894003200;
constexpr std::int64_t kWindow = 300;  // the default window [s]
const std::string kAddress = "192.0.2.7";

// Ten failures, one a second from kT0.
void fail_ten_times(LoginLimiter& limiter, const std::string& address) {
  for (int i = 0; i < 10; ++i)
    limiter.record_failure(address, kT0 + i);
}

TEST(LoginLimiter, NineFailuresDoNotLock) {
  LoginLimiter limiter;
  for (int i = 0; i < 9; ++i) {
    EXPECT_EQ(limiter.retry_after(kAddress, kT0 + i), 0) << i;
    limiter.record_failure(kAddress, kT0 + i);
  }
  EXPECT_EQ(limiter.retry_after(kAddress, kT0 + 9), 0);
}

TEST(LoginLimiter, TenFailuresLockTheEleventhAttempt) {
  LoginLimiter limiter;
  fail_ten_times(limiter, kAddress);
  const auto wait = limiter.retry_after(kAddress, kT0 + 10);
  EXPECT_GT(wait, 0);
  // Until the first failure leaves the window.
  EXPECT_EQ(wait, kT0 + kWindow - (kT0 + 10));
}

TEST(LoginLimiter, UnlocksWhenTheWindowPasses) {
  LoginLimiter limiter;
  fail_ten_times(limiter, kAddress);
  EXPECT_EQ(limiter.retry_after(kAddress, kT0 + kWindow - 1), 1);
  EXPECT_EQ(limiter.retry_after(kAddress, kT0 + kWindow), 0);
  // One more failure now makes ten within the window again (kT0 + 1 .. kT0 + 9, and now).
  limiter.record_failure(kAddress, kT0 + kWindow);
  EXPECT_GT(limiter.retry_after(kAddress, kT0 + kWindow), 0);
  EXPECT_EQ(limiter.retry_after(kAddress, kT0 + kWindow + 1), 0);
}

TEST(LoginLimiter, FailuresOutsideTheWindowDoNotCount) {
  LoginLimiter limiter;
  for (int i = 0; i < 9; ++i)
    limiter.record_failure(kAddress, kT0);
  limiter.record_failure(kAddress, kT0 + kWindow);
  EXPECT_EQ(limiter.retry_after(kAddress, kT0 + kWindow), 0);
}

TEST(LoginLimiter, SuccessClearsTheFailures) {
  LoginLimiter limiter;
  for (int i = 0; i < 9; ++i)
    limiter.record_failure(kAddress, kT0 + i);
  limiter.record_success(kAddress);
  // A fresh count: nine more failures still do not lock.
  for (int i = 0; i < 9; ++i)
    limiter.record_failure(kAddress, kT0 + 20 + i);
  EXPECT_EQ(limiter.retry_after(kAddress, kT0 + 30), 0);
  limiter.record_failure(kAddress, kT0 + 30);
  EXPECT_GT(limiter.retry_after(kAddress, kT0 + 30), 0);
  limiter.record_success(kAddress);
  EXPECT_EQ(limiter.retry_after(kAddress, kT0 + 30), 0);
}

TEST(LoginLimiter, AddressesAreIndependent) {
  LoginLimiter limiter;
  fail_ten_times(limiter, kAddress);
  EXPECT_GT(limiter.retry_after(kAddress, kT0 + 10), 0);
  EXPECT_EQ(limiter.retry_after("192.0.2.8", kT0 + 10), 0);
  EXPECT_EQ(limiter.retry_after("::1", kT0 + 10), 0);
  limiter.record_success("192.0.2.8");
  EXPECT_GT(limiter.retry_after(kAddress, kT0 + 10), 0);
}

TEST(LoginLimiter, LimitsAreConfigurable) {
  LoginLimiter limiter(3, 60);
  for (int i = 0; i < 3; ++i)
    limiter.record_failure(kAddress, kT0);
  EXPECT_EQ(limiter.retry_after(kAddress, kT0 + 1), 59);
  EXPECT_EQ(limiter.retry_after(kAddress, kT0 + 60), 0);
}

}  // namespace
}  // namespace incise::server
