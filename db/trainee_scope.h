#pragma once
// Whose training records a list holds: everyone's (admins), one trainee's
// (the trainee themself), or an instructor's own and those of the trainees assigned to them
// (trainee_instructors).
#include <cstdint>
#include <string>
#include <string_view>

namespace incise::db {

struct TraineeScope {
  enum class Kind { everyone, trainee, instructor };
  Kind kind = Kind::everyone;
  std::int64_t user_id = 0;  // the trainee, or the instructor

  static TraineeScope everyone() { return {}; }
  static TraineeScope of_trainee(std::int64_t id) { return {Kind::trainee, id}; }
  static TraineeScope of_instructor(std::int64_t id) { return {Kind::instructor, id}; }

  // "WHERE <condition on column> " with the parameter ?1 (bind user_id to 1), or "" for
  // everyone. column names the row's trainee (or user) id, e.g. "se.trainee_id".
  std::string where(std::string_view column) const {
    const std::string c(column);
    switch (kind) {
      case Kind::everyone:
        return "";
      case Kind::trainee:
        return "WHERE " + c + " = ?1 ";
      case Kind::instructor:
        return "WHERE (" + c + " = ?1 OR " + c +
               " IN (SELECT trainee_id FROM trainee_instructors WHERE instructor_id = ?1)) ";
    }
    return "";
  }
  bool binds() const { return kind != Kind::everyone; }
};

}  // namespace incise::db
