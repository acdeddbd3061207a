#pragma once
// Instructor review of attempts: annotations at a time of the recording, score adjustments (an
// instructor decides the attempt passed or not, with a reason; the latest one counts), and the
// expert runs that make the tasks' benchmarks.

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

// One metric of one expert run.
struct ExpertScore {
  std::int64_t session_id = 0;
  std::string task;
  std::string metric;
  std::string unit;
  double value = 0;
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

  // Expert runs: attempts whose scores make their task's benchmark. Marking twice, or unmarking
  // an unmarked session, changes nothing.
  void set_expert_run(std::int64_t session_id, bool expert, std::int64_t by, std::int64_t now);
  bool is_expert_run(std::int64_t session_id);
  // Every score of every expert run: task, metric, unit, value, oldest first.
  std::vector<ExpertScore> expert_scores();

 private:
  Database& db_;
};

}  // namespace incise::db
