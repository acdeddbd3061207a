#pragma once
// Instructor review of attempts: annotations at a time of the recording, and score adjustments
// (an instructor decides the attempt passed or not, with a reason; the latest one counts).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "db/database.h"

namespace incise::db {

struct Annotation {
  std::int64_t id = 0;
  std::int64_t session_id = 0;
  std::int64_t author_id = 0;
  std::string author;  // username
  double t_s = 0;      // seconds into the recording
  std::string text;
  std::int64_t created_at = 0;
};

struct ScoreAdjustment {
  std::int64_t id = 0;
  std::int64_t session_id = 0;
  std::int64_t author_id = 0;
  std::string author;
  bool passed = false;
  std::string reason;
  std::int64_t created_at = 0;
};

class ReviewsRepo {
 public:
  explicit ReviewsRepo(Database& db) : db_(db) {}

  Annotation add_annotation(std::int64_t session_id, std::int64_t author_id, double t_s,
                            const std::string& text, std::int64_t now);
  // In time order.
  std::vector<Annotation> annotations(std::int64_t session_id);

  ScoreAdjustment adjust(std::int64_t session_id, std::int64_t author_id, bool passed,
                         const std::string& reason, std::int64_t now);
  // Oldest first; the last one is in force.
  std::vector<ScoreAdjustment> adjustments(std::int64_t session_id);
  // The adjustment in force per session, for every session of a trainee.
  std::vector<ScoreAdjustment> latest_adjustments(std::int64_t trainee_id);

 private:
  Database& db_;
};

}  // namespace incise::db
