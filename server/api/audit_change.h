#pragma once
// What an audited change changed, for the audit log's before and after (db/audit_repo.h).
#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "db/database.h"

namespace incise::server::api {

struct ChangedFields {
  nlohmann::json before = nlohmann::json::object();
  nlohmann::json after = nlohmann::json::object();
};

// The fields in which `before` and `after` differ, each keyed by its path ("kind",
// "modules/0/tasks/2/thresholds/1/max"): the value before (null where it was added) and after
// (null where it was removed). Equal documents give two empty objects. A null `before` (a
// creation) or `after` (a removal) is kept whole on its other side.
ChangedFields changed_fields(const nlohmann::json& before, const nlohmann::json& after);

// Records `action` with what changed between `before` and `after` (null for none).
void audit_change(db::Database& db, std::optional<std::int64_t> user_id, const std::string& action,
                  const std::string& detail, std::int64_t now, const nlohmann::json& before,
                  const nlohmann::json& after);

}  // namespace incise::server::api
