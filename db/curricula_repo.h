#pragma once
// Curriculum definitions, stored as JSON text. Validation belongs to curriculum/; this stores
// what the caller has validated.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "db/database.h"

namespace incise::db {

struct CurriculumRecord {
  std::int64_t id = 0;
  std::string name;
  std::string definition_json;
  std::int64_t created_at = 0;
};

class CurriculaRepo {
 public:
  explicit CurriculaRepo(Database& db) : db_(db) {}
  // Throws Conflict when the name is taken.
  CurriculumRecord create(const std::string& name, const std::string& definition_json,
                          std::int64_t now);
  std::vector<CurriculumRecord> list();
  std::optional<CurriculumRecord> find(std::int64_t id);
  // Replaces the name and definition (validated by the caller). Throws NotFound for an unknown
  // id, Conflict when another curriculum has the name.
  void update(std::int64_t id, const std::string& name, const std::string& definition_json);

 private:
  Database& db_;
};

}  // namespace incise::db
