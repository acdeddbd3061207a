#pragma once
// Login sessions behind the HttpOnly cookie. Only the SHA-256 of a token is stored.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "db/database.h"
#include "db/users_repo.h"

namespace incise::db {

class AuthSessionsRepo {
 public:
  explicit AuthSessionsRepo(Database& db) : db_(db) {}

  // Starts a session for the user; returns the token for the cookie.
  std::string create(std::int64_t user_id, std::int64_t now, std::int64_t ttl_s);
  // The session's user if the token is known and not expired; slides the expiry to now + ttl_s
  // when that moves it (either way) by more than ttl_s / 100, so that most requests only read.
  std::optional<User> touch(std::string_view token, std::int64_t now, std::int64_t ttl_s);
  void remove(std::string_view token);
  // Ends every session of the user but the one of `keep` (after they changed their password, a
  // cookie someone else holds stops working).
  void remove_others(std::int64_t user_id, std::string_view keep);
  // Deletes expired sessions; returns how many.
  int purge_expired(std::int64_t now);

 private:
  Database& db_;
};

}  // namespace incise::db
