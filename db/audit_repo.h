#pragma once
// Append-only audit log of administrative changes. Never holds secrets (no passwords, tokens).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "db/database.h"

namespace incise::db {

struct AuditEntry {
  std::int64_t id = 0;
  std::int64_t at = 0;
  std::optional<std::int64_t> user_id;
  std::string action;
  std::string detail;
};

class AuditRepo {
 public:
  explicit AuditRepo(Database& db) : db_(db) {}
  void record(std::optional<std::int64_t> user_id, const std::string& action,
              const std::string& detail, std::int64_t now);
  std::vector<AuditEntry> list(int limit = 200);

 private:
  Database& db_;
};

}  // namespace incise::db
