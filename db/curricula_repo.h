#pragma once
// Curriculum definitions, stored as JSON text. Validation belongs to curriculum/; this stores
// what the caller has validated.
#include <cstdint>
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

 private:
  Database& db_;
};

}  // namespace incise::db
