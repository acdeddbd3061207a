#include "server/api/audit_change.h"

#include <map>

#include "db/audit_repo.h"

namespace incise::server::api {

namespace {
// A JSON pointer without its leading '/' and with its escapes undone ("~1" is '/', "~0" is '~'):
// what an admin reads in the log.
std::string readable_path(const std::string& pointer) {
  std::string out;
  for (std::size_t i = pointer.empty() ? 0 : 1; i < pointer.size(); ++i) {
    if (pointer[i] == '~' && i + 1 < pointer.size()) {
      out += pointer[i + 1] == '1' ? '/' : '~';
      ++i;
    } else {
      out += pointer[i];
    }
  }
  return out;
}

nlohmann::json value_at(const nlohmann::json& doc, const std::string& pointer) {
  const nlohmann::json::json_pointer at(pointer);
  return doc.contains(at) ? doc.at(at) : nlohmann::json(nullptr);
}

bool is_list_of_values(const nlohmann::json& value) {
  if (!value.is_array()) return false;
  for (const auto& element : value)
    if (element.is_structured()) return false;
  return true;
}
}  // namespace

ChangedFields changed_fields(const nlohmann::json& before, const nlohmann::json& after) {
  ChangedFields out;
  if (before.is_null() || after.is_null()) {
    if (!before.is_null()) out.before = before;
    if (!after.is_null()) out.after = after;
    return out;
  }
  // A JSON Patch from before to after names every changed place once (add, remove, replace).
  std::map<std::string, std::size_t> appended;  // per array: the "-" appends seen so far
  for (const auto& op : nlohmann::json::diff(before, after)) {
    const auto pointer = op.at("path").get<std::string>();
    // "-" (append) is not a place: the k-th append to an array of n elements lands at n + k.
    std::string place = pointer;
    if (place.size() >= 2 && place.ends_with("/-")) {
      const auto array_path = place.substr(0, place.size() - 2);
      const auto array = value_at(before, array_path);
      const auto index = (array.is_array() ? array.size() : 0) + appended[array_path]++;
      place = array_path + "/" + std::to_string(index);
    }
    // A list of plain values (instructor ids) reads best whole: [2] -> [], not "0: 2 -> null".
    const auto parent = place.substr(0, place.rfind('/'));
    if (!place.empty() && (is_list_of_values(value_at(before, parent)) ||
                           is_list_of_values(value_at(after, parent)))) {
      const auto key = readable_path(parent);
      out.before[key] = value_at(before, parent);
      out.after[key] = value_at(after, parent);
      continue;
    }
    const auto kind = op.at("op").get<std::string>();
    const auto key = readable_path(place);
    out.before[key] = kind == "add" ? nlohmann::json(nullptr) : value_at(before, place);
    out.after[key] = kind == "remove" ? nlohmann::json(nullptr) : value_at(after, place);
  }
  return out;
}

void audit_change(db::Database& db, std::optional<std::int64_t> user_id, const std::string& action,
                  const std::string& detail, std::int64_t now, const nlohmann::json& before,
                  const nlohmann::json& after) {
  const auto changed = changed_fields(before, after);
  const auto text = [](const nlohmann::json& fields) {
    return fields.empty() ? std::string() : fields.dump();
  };
  db::AuditRepo(db).record(user_id, action, detail, now, text(changed.before), text(changed.after));
}

}  // namespace incise::server::api
