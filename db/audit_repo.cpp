#include "db/audit_repo.h"

#include "db/statement.h"

namespace incise::db {

void AuditRepo::record(std::optional<std::int64_t> user_id, const std::string& action,
                       const std::string& detail, std::int64_t now) {
  db_.prepare("INSERT INTO audit_log (at, user_id, action, detail) VALUES (?, ?, ?, ?)")
      .bind(1, now)
      .bind(2, user_id)
      .bind(3, action)
      .bind(4, detail)
      .run();
}

std::vector<AuditEntry> AuditRepo::list(int limit) {
  auto q =
      db_.prepare("SELECT id, at, user_id, action, detail FROM audit_log ORDER BY id DESC LIMIT ?");
  q.bind(1, limit);
  std::vector<AuditEntry> out;
  while (q.step()) {
    out.push_back(AuditEntry{q.int64(0), q.int64(1), q.optional_int64(2), q.text(3), q.text(4)});
  }
  return out;
}

}  // namespace incise::db
