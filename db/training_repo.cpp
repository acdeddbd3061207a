#include "db/training_repo.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <set>
#include <stdexcept>
#include <string_view>

#include "db/db_error.h"
#include "db/statement.h"
#include "db/transaction.h"

namespace incise::db {

namespace {

constexpr const char* session_columns =
    "SELECT se.id, se.trainee_id, u.username, se.station_id, COALESCE(st.name, ''), se.task, "
    "se.state, se.started_at, se.ended_at FROM sessions se JOIN users u ON u.id = se.trainee_id "
    "LEFT JOIN stations st ON st.id = se.station_id ";

SessionRecord read_session(const Statement& q) {
  return SessionRecord{q.int64(0), q.int64(1), q.text(2),           q.optional_int64(3), q.text(4),
                       q.text(5),  q.text(6),  q.optional_int64(7), q.optional_int64(8)};
}

// Checked before the transaction, so that bad input is reported as such and writes nothing.
void check_scores(std::span<const ScoreInput> scores) {
  std::set<std::string_view> seen;
  for (const ScoreInput& s : scores) {
    if (s.metric.empty()) throw std::invalid_argument("score metric name is empty");
    if (!seen.insert(s.metric).second)
      throw std::invalid_argument("score metric " + s.metric + " appears twice");
    if (!std::isfinite(s.value))
      throw std::invalid_argument("score " + s.metric + " is not finite");
    if (s.threshold_op != "" && s.threshold_op != "<=" && s.threshold_op != ">=")
      throw std::invalid_argument("score " + s.metric + " has threshold op '" + s.threshold_op +
                                  "', not <= or >=");
    if (!std::isfinite(s.threshold_value))
      throw std::invalid_argument("score " + s.metric + " has a threshold that is not finite");
  }
}

}  // namespace

std::int64_t TrainingRepo::create_session(std::int64_t trainee_id,
                                          std::optional<std::int64_t> station_id,
                                          const std::string& task, std::int64_t now,
                                          std::optional<std::int64_t> booking_id,
                                          const std::string& node_id) {
  return db_
      .prepare(
          "INSERT INTO sessions (trainee_id, station_id, task, state, created_at, booking_id, "
          "node_id) VALUES (?, ?, ?, 'created', ?, ?, ?) RETURNING id")
      .bind(1, trainee_id)
      .bind(2, station_id)
      .bind(3, task)
      .bind(4, now)
      .bind(5, booking_id)
      .bind(6, node_id.empty() ? std::nullopt : std::optional<std::string>(node_id))
      .insert();
}

bool TrainingRepo::set_session_state(std::int64_t id, const std::string& state, std::int64_t now) {
  // started_at is set on the first move to running; ended_at when the session ends.
  db_.prepare(
         "UPDATE sessions SET state = ?1, started_at = CASE WHEN ?1 = 'running' AND started_at IS "
         "NULL THEN ?2 ELSE started_at END, ended_at = CASE WHEN ?1 IN ('finished', 'aborted') "
         "THEN ?2 ELSE ended_at END WHERE id = ?3 AND state NOT IN ('finished', 'aborted')")
      .bind(1, state)
      .bind(2, now)
      .bind(3, id)
      .run();
  if (db_.changes() > 0) return true;
  if (!find_session(id)) throw NotFound("session " + std::to_string(id) + " does not exist");
  return false;
}

std::int64_t TrainingRepo::add_recording(std::int64_t session_id, double duration_s,
                                         std::int64_t now) {
  return db_
      .prepare(
          "INSERT INTO recordings (session_id, duration_s, created_at) VALUES (?, ?, ?) RETURNING "
          "id")
      .bind(1, session_id)
      .bind(2, duration_s)
      .bind(3, now)
      .insert();
}

std::int64_t TrainingRepo::add_score(std::int64_t session_id, const std::string& metric,
                                     double value, const std::string& unit, bool passed,
                                     std::int64_t now) {
  return db_
      .prepare(
          "INSERT INTO scores (session_id, metric, value, unit, passed, created_at) VALUES (?, "
          "?, ?, ?, ?, ?) RETURNING id")
      .bind(1, session_id)
      .bind(2, metric)
      .bind(3, value)
      .bind(4, unit)
      .bind(5, passed ? 1 : 0)
      .bind(6, now)
      .insert();
}

void TrainingRepo::add_scores(std::int64_t session_id, std::span<const ScoreInput> scores,
                              std::int64_t now) {
  check_scores(scores);
  Transaction tx(db_);
  auto session = db_.prepare("SELECT 1 FROM sessions WHERE id = ?");
  if (!session.bind(1, session_id).step())
    throw NotFound("session " + std::to_string(session_id) + " does not exist");
  auto insert = db_.prepare(
      "INSERT INTO scores (session_id, metric, value, unit, passed, created_at, threshold_op, "
      "threshold_value, criterion) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?) ON CONFLICT (session_id, "
      "metric) DO UPDATE SET value = excluded.value, unit = excluded.unit, passed = "
      "excluded.passed, created_at = excluded.created_at, threshold_op = excluded.threshold_op, "
      "threshold_value = excluded.threshold_value, criterion = excluded.criterion");
  for (const ScoreInput& s : scores) {
    const bool judged = !s.threshold_op.empty();
    insert.reset();
    insert.bind(1, session_id)
        .bind(2, s.metric)
        .bind(3, s.value)
        .bind(4, s.unit)
        .bind(5, s.passed ? 1 : 0)
        .bind(6, now)
        .bind(7, judged ? std::optional<std::string>(s.threshold_op) : std::nullopt)
        .bind(8, judged ? std::optional<double>(s.threshold_value) : std::nullopt)
        .bind(9, s.criterion ? 1 : 0)
        .run();
  }
  tx.commit();
}

std::optional<SessionRecord> TrainingRepo::find_session(std::int64_t id) {
  auto q = db_.prepare(std::string(session_columns) + "WHERE se.id = ?");
  q.bind(1, id);
  if (!q.step()) return std::nullopt;
  return read_session(q);
}

std::vector<SessionRecord> TrainingRepo::sessions(const TraineeScope& scope) {
  auto q = db_.prepare(std::string(session_columns) + scope.where("se.trainee_id") +
                       "ORDER BY se.created_at DESC, se.id DESC");
  if (scope.binds()) q.bind(1, scope.user_id);
  std::vector<SessionRecord> out;
  while (q.step())
    out.push_back(read_session(q));
  return out;
}

std::vector<RecordingRecord> TrainingRepo::recordings(const TraineeScope& scope) {
  auto q = db_.prepare(
      std::string(
          "SELECT r.id, r.session_id, u.username, se.task, r.duration_s, r.created_at, r.state "
          "FROM recordings r JOIN sessions se ON se.id = r.session_id "
          "JOIN users u ON u.id = se.trainee_id ") +
      scope.where("se.trainee_id") + "ORDER BY r.created_at DESC, r.id DESC");
  if (scope.binds()) q.bind(1, scope.user_id);
  std::vector<RecordingRecord> out;
  while (q.step()) {
    out.push_back(RecordingRecord{q.int64(0), q.int64(1), q.text(2), q.text(3), q.real(4),
                                  q.int64(5), q.text(6)});
  }
  return out;
}

namespace {

constexpr const char* kScoreSelect =
    "SELECT sc.id, sc.session_id, u.username, se.task, sc.metric, sc.value, sc.unit, sc.passed, "
    "sc.created_at, COALESCE(sc.threshold_op, ''), COALESCE(sc.threshold_value, 0), sc.criterion "
    "FROM scores sc "
    "JOIN sessions se ON se.id = sc.session_id JOIN users u ON u.id = se.trainee_id ";

std::vector<ScoreRecord> read_scores(Statement& q) {
  std::vector<ScoreRecord> out;
  while (q.step()) {
    out.push_back(ScoreRecord{q.int64(0), q.int64(1), q.text(2), q.text(3), q.text(4), q.real(5),
                              q.text(6), q.int64(7) != 0, q.int64(8), q.text(9), q.real(10),
                              q.int64(11) != 0});
  }
  return out;
}

}  // namespace

std::vector<ScoreRecord> TrainingRepo::scores(const TraineeScope& scope) {
  auto q = db_.prepare(std::string(kScoreSelect) + scope.where("se.trainee_id") +
                       "ORDER BY sc.created_at DESC, sc.id DESC");
  if (scope.binds()) q.bind(1, scope.user_id);
  return read_scores(q);
}

std::vector<ScoreRecord> TrainingRepo::session_scores(std::int64_t session_id) {
  auto q = db_.prepare(std::string(kScoreSelect) + "WHERE sc.session_id = ? ORDER BY sc.id");
  q.bind(1, session_id);
  return read_scores(q);
}

void TrainingRepo::set_signal(std::int64_t session_id, const std::string& name,
                              const SessionSignal& signal) {
  if (!std::isfinite(signal.interval_s) || signal.interval_s <= 0) {
    throw std::invalid_argument("signal " + name + ": interval_s must be a finite number > 0");
  }
  std::vector<std::uint8_t> bytes(signal.values.size() * sizeof(double));
  for (std::size_t i = 0; i < signal.values.size(); ++i) {
    const double v = signal.values[i];
    if (!std::isfinite(v)) {
      throw std::invalid_argument("signal " + name + ": value " + std::to_string(i) +
                                  " is not finite");
    }
    // Little-endian, byte by byte: the file reads the same on any machine.
    std::uint64_t u = 0;
    std::memcpy(&u, &v, sizeof u);
    for (std::size_t b = 0; b < sizeof u; ++b)
      bytes[i * sizeof u + b] = static_cast<std::uint8_t>(u >> (8 * b));
  }
  db_.prepare(
         "INSERT INTO session_signals (session_id, name, interval_s, data) VALUES (?, ?, ?, ?) "
         "ON CONFLICT (session_id, name) DO UPDATE SET interval_s = excluded.interval_s, "
         "data = excluded.data")
      .bind(1, session_id)
      .bind(2, name)
      .bind(3, signal.interval_s)
      .bind_blob(4, bytes)
      .run();
}

std::optional<SessionSignal> TrainingRepo::signal(std::int64_t session_id,
                                                  const std::string& name) {
  auto q =
      db_.prepare("SELECT interval_s, data FROM session_signals WHERE session_id = ? AND name = ?");
  q.bind(1, session_id);
  q.bind(2, name);
  if (!q.step()) return std::nullopt;
  SessionSignal signal;
  signal.interval_s = q.real(0);
  const auto bytes = q.blob(1);
  signal.values.resize(bytes.size() / sizeof(double));
  for (std::size_t i = 0; i < signal.values.size(); ++i) {
    std::uint64_t u = 0;
    for (std::size_t b = 0; b < sizeof u; ++b)
      u |= static_cast<std::uint64_t>(bytes[i * sizeof u + b]) << (8 * b);
    std::memcpy(&signal.values[i], &u, sizeof u);
  }
  return signal;
}

}  // namespace incise::db
