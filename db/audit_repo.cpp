#include "db/audit_repo.h"

#include "db/statement.h"

namespace incise::db {

void AuditRepo::record(std::optional<std::int64_t> user_id, const std::string& action,
                       const std::string& detail, std::int64_t now, const std::string& before_json,
                       const std::string& after_json) {
  const auto text_or_null = [](const std::string& s) {
    return s.empty() ? std::nullopt : std::optional<std::string>(s);
  };
  db_.prepare(
         "INSERT INTO audit_log (at, user_id, action, detail, before_json, after_json) VALUES "
         "(?, ?, ?, ?, ?, ?)")
      .bind(1, now)
      .bind(2, user_id)
      .bind(3, action)
      .bind(4, detail)
      .bind(5, text_or_null(before_json))
      .bind(6, text_or_null(after_json))
      .run();
}

std::vector<AuditEntry> AuditRepo::list(int limit) {
  auto q = db_.prepare(
      "SELECT id, at, user_id, action, detail, COALESCE(before_json, ''), COALESCE(after_json, '') "
      "FROM audit_log ORDER BY id DESC LIMIT ?");
  q.bind(1, limit);
  std::vector<AuditEntry> out;
  while (q.step()) {
    out.push_back(AuditEntry{q.int64(0), q.int64(1), q.optional_int64(2), q.text(3), q.text(4),
                             q.text(5), q.text(6)});
  }
  return out;
}

}  // namespace incise::db
