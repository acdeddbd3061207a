#include "db/auth_sessions_repo.h"

#include <cstdlib>

#include "db/password.h"
#include "db/statement.h"

namespace incise::db {

std::string AuthSessionsRepo::create(std::int64_t user_id, std::int64_t now, std::int64_t ttl_s) {
  std::string token = random_token();
  db_.prepare(
         "INSERT INTO auth_sessions (token_hash, user_id, created_at, expires_at) VALUES (?, ?, "
         "?, ?)")
      .bind_blob(1, token_hash(token))
      .bind(2, user_id)
      .bind(3, now)
      .bind(4, now + ttl_s)
      .run();
  return token;
}

std::optional<User> AuthSessionsRepo::touch(std::string_view token, std::int64_t now,
                                            std::int64_t ttl_s) {
  const auto hash = token_hash(token);
  // A disabled user's sessions are deleted when they are disabled; the join refuses them anyway.
  auto q = db_.prepare(
      "SELECT u.id, s.expires_at FROM auth_sessions s JOIN users u ON u.id = s.user_id "
      "WHERE s.token_hash = ? AND s.expires_at > ? AND u.disabled_at IS NULL");
  q.bind_blob(1, hash).bind(2, now);
  if (!q.step()) return std::nullopt;
  const auto user_id = q.int64(0);
  // The expiry slides only when it would move by more than a hundredth of the lifetime (7 min of
  // 12 h): most requests then only read, which is what lets many run side by side.
  const bool slide = std::llabs(now + ttl_s - q.int64(1)) > ttl_s / 100;
  // End the read before writing. A write while the SELECT is still open would upgrade its read
  // transaction, and if a session thread's connection has committed since the read began, SQLite
  // answers SQLITE_BUSY_SNAPSHOT at once, without waiting on the busy timeout.
  q.reset();
  if (slide) {
    db_.prepare("UPDATE auth_sessions SET expires_at = ? WHERE token_hash = ?")
        .bind(1, now + ttl_s)
        .bind_blob(2, hash)
        .run();
  }
  return UsersRepo(db_).find(user_id);
}

void AuthSessionsRepo::remove(std::string_view token) {
  db_.prepare("DELETE FROM auth_sessions WHERE token_hash = ?")
      .bind_blob(1, token_hash(token))
      .run();
}

void AuthSessionsRepo::remove_others(std::int64_t user_id, std::string_view keep) {
  db_.prepare("DELETE FROM auth_sessions WHERE user_id = ? AND token_hash != ?")
      .bind(1, user_id)
      .bind_blob(2, token_hash(keep))
      .run();
}

int AuthSessionsRepo::purge_expired(std::int64_t now) {
  db_.prepare("DELETE FROM auth_sessions WHERE expires_at <= ?").bind(1, now).run();
  return db_.changes();
}

}  // namespace incise::db
