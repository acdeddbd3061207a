#pragma once
// Training records: simulation sessions, their recordings and their scores.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "db/database.h"
#include "db/trainee_scope.h"

namespace incise::db {

struct SessionRecord {
  std::int64_t id = 0;
  std::int64_t trainee_id = 0;
  std::string trainee;  // username
  std::optional<std::int64_t> station_id;
  std::string station;  // name, empty when none
  std::string task;
  std::string state;  // created, running, paused, finished, aborted
  std::optional<std::int64_t> started_at;
  std::optional<std::int64_t> ended_at;
};

struct RecordingRecord {
  std::int64_t id = 0;
  std::int64_t session_id = 0;
  std::string trainee;
  std::string task;
  double duration_s = 0;
  std::int64_t created_at = 0;
  std::string state;  // "recording" while the recorder appends, then "complete"
};

struct ScoreRecord {
  std::int64_t id = 0;
  std::int64_t session_id = 0;
  std::string trainee;
  std::string task;
  std::string metric;
  double value = 0;
  std::string unit;
  bool passed = false;
  std::int64_t created_at = 0;
  std::string threshold_op{};  // "<=" or ">=" it was judged against; "" when not known
  double threshold_value = 0;  // in the score's unit
  bool criterion = false;      // a completion criterion of the task, not a metric's threshold
};

// One metric's score of an attempt, for add_scores.
struct ScoreInput {
  std::string metric;
  double value = 0;  // finite
  std::string unit;
  bool passed = false;
  std::string threshold_op{};  // "<=", ">=", or "" for none
  double threshold_value = 0;  // finite
  bool criterion = false;      // a completion criterion of the task (Task::completion)
};

// A signal the simulation sampled during a session (session_signals), e.g. "damage_index".
struct SessionSignal {
  double interval_s = 0;       // between samples, the first at interval_s after the start
  std::vector<double> values;  // one per sample
};

class TrainingRepo {
 public:
  explicit TrainingRepo(Database& db) : db_(db) {}

  // #booking_id: the booking the session runs in, which its end completes
  // (BookingsRepo::complete_for_session); none for a session without one (an instructor's).
  std::int64_t create_session(std::int64_t trainee_id, std::optional<std::int64_t> station_id,
                              const std::string& task, std::int64_t now,
                              std::optional<std::int64_t> booking_id = std::nullopt,
                              const std::string& node_id = {});  // the node running it, if live
  // Throws ConstraintError for an unknown state name, NotFound for an unknown id. An ended session
  // (finished or aborted) stays as it ended: false then, and nothing changes (a pause answered a
  // moment after the session thread wrote "finished" must not undo it).
  bool set_session_state(std::int64_t id, const std::string& state, std::int64_t now);
  std::int64_t add_recording(std::int64_t session_id, double duration_s, std::int64_t now);
  // Stores (or replaces) a session's signal. Throws std::invalid_argument for interval_s <= 0 or
  // not finite, or a non-finite value.
  void set_signal(std::int64_t session_id, const std::string& name, const SessionSignal& signal);
  std::optional<SessionSignal> signal(std::int64_t session_id, const std::string& name);
  std::int64_t add_score(std::int64_t session_id, const std::string& metric, double value,
                         const std::string& unit, bool passed, std::int64_t now);
  // Stores an attempt's scores in ONE transaction: all of them or, on any error, none. A score
  // for a metric the session already has replaces it (a re-scored attempt). Throws
  // std::invalid_argument before writing for an empty or repeated metric name or a non-finite
  // value, NotFound for an unknown session.
  void add_scores(std::int64_t session_id, std::span<const ScoreInput> scores, std::int64_t now);

  std::optional<SessionRecord> find_session(std::int64_t id);

  // `trainee_id` restricts to one trainee's records. Newest first.
  // Newest first, of the trainees in scope.
  std::vector<SessionRecord> sessions(const TraineeScope& scope);
  std::vector<RecordingRecord> recordings(const TraineeScope& scope);
  std::vector<ScoreRecord> scores(const TraineeScope& scope);
  // One session's scores, in the order they were stored.
  std::vector<ScoreRecord> session_scores(std::int64_t session_id);
  // Everyone's (no trainee_id) or one trainee's.
  std::vector<SessionRecord> sessions(std::optional<std::int64_t> trainee_id = std::nullopt) {
    return sessions(scope_of(trainee_id));
  }
  std::vector<RecordingRecord> recordings(std::optional<std::int64_t> trainee_id = std::nullopt) {
    return recordings(scope_of(trainee_id));
  }
  std::vector<ScoreRecord> scores(std::optional<std::int64_t> trainee_id = std::nullopt) {
    return scores(scope_of(trainee_id));
  }

 private:
  static TraineeScope scope_of(std::optional<std::int64_t> trainee_id) {
    return trainee_id ? TraineeScope::of_trainee(*trainee_id) : TraineeScope::everyone();
  }

  Database& db_;
};

}  // namespace incise::db
