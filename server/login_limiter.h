#pragma once
// Limits password guessing (docs/security.md, "Logins"). Three counts of failures are kept: per
// account and address together, per address (over all accounts) and per account (over all
// addresses). Each allows a few failures freely and then makes the next attempt wait, doubling
// the wait with each further failure up to a ceiling. A success clears only the count of its own
// account at its own address, so logging into one's own account does not buy guesses at another.
// An address from which an account has logged in recently is "known" for that account: the
// address-wide and account-wide counts do not hold it back, so the real user is not locked out
// by guesses from elsewhere (or from others behind the same address at other accounts).
// Thread-safe; memory is bounded however many accounts and addresses are tried.
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <string_view>

namespace incise::server {

struct LoginPolicy {
  int free_per_pair = 5;               // failures of one account from one address before any wait
  int free_per_address = 20;           // failures from one address, over all accounts
  int free_per_account = 20;           // failures at one account, over all addresses
  std::int64_t max_wait_s = 900;       // the ceiling of the doubling wait
  std::int64_t forget_after_s = 3600;  // a count with no failure for this long starts again
  std::int64_t known_for_s = 30 * 86400;  // how long a successful login makes an address known
  std::size_t max_entries = 50000;        // per table; the oldest are dropped beyond it
};

class LoginLimiter {
 public:
  explicit LoginLimiter(LoginPolicy policy = {}) : policy_(policy) {}

  // Seconds until `account` may be tried from `address` again; 0 when it may be tried now.
  std::int64_t retry_after(std::string_view account, std::string_view address, std::int64_t now);
  void record_failure(std::string_view account, std::string_view address, std::int64_t now);
  void record_success(std::string_view account, std::string_view address, std::int64_t now);

  const LoginPolicy& policy() const { return policy_; }

 private:
  struct Count {
    int failures = 0;
    std::int64_t last = 0;  // time of the latest failure
  };
  using Table = std::map<std::string, Count, std::less<>>;

  std::int64_t wait(const Table& table, const std::string& key, int free, std::int64_t now) const;
  void count_failure(Table& table, const std::string& key, std::int64_t now);
  bool known(const std::string& pair, std::int64_t now) const;

  LoginPolicy policy_;
  std::mutex mutex_;
  Table pairs_, addresses_, accounts_;
  std::map<std::string, std::int64_t, std::less<>> known_;  // pair -> time of its last success
};

}  // namespace incise::server
