#include "db/curricula_repo.h"

#include "db/db_error.h"
#include "db/statement.h"

namespace incise::db {

CurriculumRecord CurriculaRepo::create(const std::string& name, const std::string& definition_json,
                                       std::int64_t now) {
  std::int64_t id = 0;
  try {
    id =
        db_.prepare(
               "INSERT INTO curricula (name, definition, created_at) VALUES (?, ?, ?) RETURNING id")
            .bind(1, name)
            .bind(2, definition_json)
            .bind(3, now)
            .insert();
  } catch (const ConstraintError&) {
    throw Conflict("a curriculum named '" + name + "' already exists");
  }
  return CurriculumRecord{id, name, definition_json, now};
}

std::vector<CurriculumRecord> CurriculaRepo::list() {
  auto q = db_.prepare("SELECT id, name, definition, created_at FROM curricula ORDER BY name");
  std::vector<CurriculumRecord> out;
  while (q.step())
    out.push_back(CurriculumRecord{q.int64(0), q.text(1), q.text(2), q.int64(3)});
  return out;
}

std::optional<CurriculumRecord> CurriculaRepo::find(std::int64_t id) {
  auto q = db_.prepare("SELECT id, name, definition, created_at FROM curricula WHERE id = ?");
  q.bind(1, id);
  if (!q.step()) return std::nullopt;
  return CurriculumRecord{q.int64(0), q.text(1), q.text(2), q.int64(3)};
}

void CurriculaRepo::update(std::int64_t id, const std::string& name,
                           const std::string& definition_json) {
  try {
    auto q = db_.prepare("UPDATE curricula SET name = ?, definition = ? WHERE id = ?");
    q.bind(1, name).bind(2, definition_json).bind(3, id).run();
  } catch (const ConstraintError&) {
    throw Conflict("a curriculum named '" + name + "' already exists");
  }
  if (db_.changes() == 0) throw NotFound("curriculum " + std::to_string(id) + " does not exist");
}

}  // namespace incise::db
