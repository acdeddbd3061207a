#include "server/login_limiter.h"

#include <algorithm>

namespace incise::server {

namespace {
// Usernames are matched exactly by the database, but a guesser should not get fresh counts by
// changing the case of an ASCII letter.
std::string account_key(std::string_view account) {
  std::string key(account.substr(0, 256));
  for (auto& c : key) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return key;
}

std::string pair_key(std::string_view account, std::string_view address) {
  // A NUL cannot occur in an address, so the pair is unambiguous.
  return account_key(account) + '\0' + std::string(address);
}
}  // namespace

std::int64_t LoginLimiter::wait(const Table& table, const std::string& key, int free,
                                std::int64_t now) const {
  const auto it = table.find(key);
  if (it == table.end()) return 0;
  const auto& count = it->second;
  if (count.failures <= free || now - count.last >= policy_.forget_after_s) return 0;
  // One second after the first failure beyond the free ones, doubling with each further one.
  const int doublings = std::min(count.failures - free - 1, 30);
  const auto delay = std::min<std::int64_t>(std::int64_t{1} << doublings, policy_.max_wait_s);
  return std::max<std::int64_t>(0, count.last + delay - now);
}

void LoginLimiter::count_failure(Table& table, const std::string& key, std::int64_t now) {
  auto& count = table[key];
  if (now - count.last >= policy_.forget_after_s) count.failures = 0;
  ++count.failures;
  count.last = now;
  if (table.size() <= policy_.max_entries) return;
  // A flood of distinct names or addresses: drop what is forgotten anyway, else the oldest.
  std::erase_if(
      table, [&](const auto& entry) { return now - entry.second.last >= policy_.forget_after_s; });
  while (table.size() > policy_.max_entries) {
    table.erase(std::min_element(table.begin(), table.end(), [](const auto& a, const auto& b) {
      return a.second.last < b.second.last;
    }));
  }
}

bool LoginLimiter::known(const std::string& pair, std::int64_t now) const {
  const auto it = known_.find(pair);
  return it != known_.end() && now - it->second < policy_.known_for_s;
}

std::int64_t LoginLimiter::retry_after(std::string_view account, std::string_view address,
                                       std::int64_t now) {
  std::lock_guard lock(mutex_);
  const auto pair = pair_key(account, address);
  auto longest = wait(pairs_, pair, policy_.free_per_pair, now);
  if (!known(pair, now)) {
    longest =
        std::max(longest, wait(addresses_, std::string(address), policy_.free_per_address, now));
    longest =
        std::max(longest, wait(accounts_, account_key(account), policy_.free_per_account, now));
  }
  return longest;
}

void LoginLimiter::record_failure(std::string_view account, std::string_view address,
                                  std::int64_t now) {
  std::lock_guard lock(mutex_);
  const auto pair = pair_key(account, address);
  count_failure(pairs_, pair, now);
  // A known address mistyping its own password must not lock others out of the account.
  if (known(pair, now)) return;
  count_failure(addresses_, std::string(address), now);
  count_failure(accounts_, account_key(account), now);
}

void LoginLimiter::record_success(std::string_view account, std::string_view address,
                                  std::int64_t now) {
  std::lock_guard lock(mutex_);
  const auto pair = pair_key(account, address);
  pairs_.erase(pair);
  known_[pair] = now;
  if (known_.size() > policy_.max_entries) {
    std::erase_if(known_,
                  [&](const auto& entry) { return now - entry.second >= policy_.known_for_s; });
    while (known_.size() > policy_.max_entries) {
      known_.erase(std::min_element(known_.begin(), known_.end(), [](const auto& a, const auto& b) {
        return a.second < b.second;
      }));
    }
  }
}

}  // namespace incise::server
