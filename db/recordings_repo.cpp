#include "db/recordings_repo.h"

#include <sqlite3.h>

#include <cmath>
#include <stdexcept>

#include "db/statement.h"
#include "db/transaction.h"

namespace incise::db {

namespace {

constexpr const char* meta_columns =
    "SELECT id, session_id, scene, scene_version, seed, tick_hz, duration_s, state, created_at, "
    "final_state_hash, COALESCE(material, '') "
    "FROM recordings ";

RecordingMeta read_meta(const Statement& q) {
  return RecordingMeta{q.int64(0), q.int64(1), q.text(2),  q.text(3), q.int64(4), q.real(5),
                       q.real(6),  q.text(7),  q.int64(8), q.text(9), q.text(10)};
}

void check_duration(double duration_s) {
  if (!std::isfinite(duration_s) || duration_s < 0) {
    throw std::invalid_argument("recording duration_s must be finite and >= 0, got " +
                                std::to_string(duration_s));
  }
}

// The recording's state; NotFound when there is no such recording.
std::string state_of(Database& db, std::int64_t recording_id) {
  auto q = db.prepare("SELECT state FROM recordings WHERE id = ?");
  q.bind(1, recording_id);
  if (!q.step()) throw NotFound("recording " + std::to_string(recording_id) + " does not exist");
  return q.text(0);
}

void require_open(Database& db, std::int64_t recording_id) {
  if (state_of(db, recording_id) != "recording")
    throw Conflict("recording " + std::to_string(recording_id) + " is already complete");
}

}  // namespace

std::int64_t RecordingsRepo::create(std::int64_t session_id, const std::string& scene,
                                    const std::string& scene_version, std::int64_t seed,
                                    double tick_hz, std::int64_t now, const std::string& material) {
  if (!std::isfinite(tick_hz) || tick_hz <= 0) {
    throw std::invalid_argument("recording tick_hz must be finite and > 0, got " +
                                std::to_string(tick_hz));
  }
  return db_
      .prepare(
          "INSERT INTO recordings (session_id, scene, scene_version, seed, tick_hz, duration_s, "
          "state, created_at, material) VALUES (?, ?, ?, ?, ?, 0, 'recording', ?, ?) RETURNING id")
      .bind(1, session_id)
      .bind(2, scene)
      .bind(3, scene_version)
      .bind(4, seed)
      .bind(5, tick_hz)
      .bind(6, now)
      .bind(7, material.empty() ? std::optional<std::string>() : std::optional(material))
      .insert();
}

void RecordingsRepo::append_chunk(std::int64_t recording_id, std::int64_t seq, std::int64_t t0_us,
                                  std::span<const std::uint8_t> data, double duration_s) {
  check_duration(duration_s);
  if (t0_us < 0) throw std::invalid_argument("chunk t0_us must be >= 0");
  // IMMEDIATE: the next-seq check and the insert cannot interleave with another writer.
  Transaction tx(db_);
  require_open(db_, recording_id);
  auto next =
      db_.prepare("SELECT COALESCE(MAX(seq) + 1, 0) FROM recording_chunks WHERE recording_id = ?");
  next.bind(1, recording_id).step();
  const std::int64_t expected = next.int64(0);
  if (seq != expected) {
    // A gap or a repeat would make the replay skip or double input: refuse it like a constraint.
    throw ConstraintError(SQLITE_CONSTRAINT, "recording " + std::to_string(recording_id) +
                                                 ": chunk seq " + std::to_string(seq) +
                                                 " is not the next one (expected " +
                                                 std::to_string(expected) + ")");
  }
  db_.prepare("INSERT INTO recording_chunks (recording_id, seq, t0_us, data) VALUES (?, ?, ?, ?)")
      .bind(1, recording_id)
      .bind(2, seq)
      .bind(3, t0_us)
      .bind_blob(4, data)
      .run();
  db_.prepare("UPDATE recordings SET duration_s = ? WHERE id = ?")
      .bind(1, duration_s)
      .bind(2, recording_id)
      .run();
  tx.commit();
}

void RecordingsRepo::finish(std::int64_t recording_id, double duration_s,
                            const std::string& final_state_hash) {
  check_duration(duration_s);
  Transaction tx(db_);
  require_open(db_, recording_id);
  db_.prepare(
         "UPDATE recordings SET state = 'complete', duration_s = ?, final_state_hash = ? "
         "WHERE id = ?")
      .bind(1, duration_s)
      .bind(2, final_state_hash)
      .bind(3, recording_id)
      .run();
  tx.commit();
}

std::optional<RecordingMeta> RecordingsRepo::find(std::int64_t recording_id) {
  auto q = db_.prepare(std::string(meta_columns) + "WHERE id = ?");
  q.bind(1, recording_id);
  if (!q.step()) return std::nullopt;
  return read_meta(q);
}

std::optional<RecordingMeta> RecordingsRepo::find_by_session(std::int64_t session_id) {
  auto q = db_.prepare(std::string(meta_columns) + "WHERE session_id = ?");
  q.bind(1, session_id);
  if (!q.step()) return std::nullopt;
  return read_meta(q);
}

std::vector<RecordingMeta> RecordingsRepo::unfinished() {
  auto q = db_.prepare(std::string(meta_columns) + "WHERE state = 'recording' ORDER BY id");
  std::vector<RecordingMeta> out;
  while (q.step())
    out.push_back(read_meta(q));
  return out;
}

std::vector<RecordingsRepo::Chunk> RecordingsRepo::chunks(std::int64_t recording_id) {
  auto q = db_.prepare(
      "SELECT seq, t0_us, data FROM recording_chunks WHERE recording_id = ? ORDER BY seq");
  q.bind(1, recording_id);
  std::vector<Chunk> out;
  while (q.step())
    out.push_back(Chunk{q.int64(0), q.int64(1), q.blob(2)});
  return out;
}

}  // namespace incise::db
