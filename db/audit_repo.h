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
  // The changed fields before and after, as JSON object texts; "" where there is none (a creation
  // has no before, a removal no after).
  std::string before_json;
  std::string after_json;
};

class AuditRepo {
 public:
  explicit AuditRepo(Database& db) : db_(db) {}
  // before_json/after_json: "" for none. Callers pass JSON texts; db/ stores them as given.
  void record(std::optional<std::int64_t> user_id, const std::string& action,
              const std::string& detail, std::int64_t now, const std::string& before_json = "",
              const std::string& after_json = "");
  std::vector<AuditEntry> list(int limit = 200);

 private:
  Database& db_;
};

}  // namespace incise::db
