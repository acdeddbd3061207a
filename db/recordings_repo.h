#pragma once
// Recordings of live sessions: what was simulated, and the recorded input log in numbered chunks.
// The recorder appends one chunk per small transaction (WAL), so a crash loses at most the chunk
// being written (docs/architecture.md, "A live session, end to end"); a replay reads the chunks
// back in order.
//
// Lifecycle: create() opens a recording in state 'recording'; append_chunk() adds chunks 0, 1,
// 2, ... and moves duration_s forward; finish() sets state 'complete'. A crash leaves the
// recording in state 'recording' with every committed chunk and the duration through the last
// one; it stays readable (find, chunks). At start-up, before it accepts sessions, the server
// calls unfinished() and marks each one complete with finish(id, meta.duration_s).
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "db/database.h"
#include "db/db_error.h"

namespace incise::db {

struct RecordingMeta {
  std::int64_t id = 0;
  std::int64_t session_id = 0;
  std::string scene;          // scene file id, e.g. "scenes/palpation.json"
  std::string scene_version;  // a hash of the scene text, so a replay can tell it changed
  std::int64_t seed = 0;      // the simulation's random seed (a uint64 seed is stored bit for bit)
  double tick_hz = 0;         // simulation rate the input was recorded at [Hz]; 0 before 002
  double duration_s = 0;      // simulated time covered by the committed chunks [s]
  std::string state;          // "recording" or "complete"
  std::int64_t created_at = 0;
  std::string final_state_hash;  // the simulation state hash at the end; "" if not known
  std::string material;  // the named material the session ran its scene with; "" for the scene's
};

class RecordingsRepo {
 public:
  explicit RecordingsRepo(Database& db) : db_(db) {}

  // Opens the recording of a session: state 'recording', duration 0. Throws
  // std::invalid_argument unless tick_hz is finite and > 0, ConstraintError when the session is
  // unknown or already has a recording (one per session). material: the named material the
  // scene runs with ("" for the scene's own constants).
  std::int64_t create(std::int64_t session_id, const std::string& scene,
                      const std::string& scene_version, std::int64_t seed, double tick_hz,
                      std::int64_t now, const std::string& material = "");

  // One small transaction: inserts chunk `seq`, starting at t0_us [µs since the start], and sets
  // the recording's duration to duration_s. seq must be the next one (0, 1, 2, ...), else
  // ConstraintError naming the expected seq, and nothing changes. Throws NotFound for an unknown
  // recording, Conflict for a complete one, std::invalid_argument for a negative or non-finite
  // duration_s or a negative t0_us.
  void append_chunk(std::int64_t recording_id, std::int64_t seq, std::int64_t t0_us,
                    std::span<const std::uint8_t> data, double duration_s);

  // Sets state 'complete', the final duration and the hash of the final simulation state ("" when
  // unknown, e.g. after a crash). Throws NotFound for an unknown recording, Conflict when it is
  // already complete, std::invalid_argument for a bad duration_s.
  void finish(std::int64_t recording_id, double duration_s,
              const std::string& final_state_hash = "");

  std::optional<RecordingMeta> find(std::int64_t recording_id);
  std::optional<RecordingMeta> find_by_session(std::int64_t session_id);
  // Recordings still in state 'recording', oldest first: at start-up, the ones a crash left open.
  std::vector<RecordingMeta> unfinished();

  struct Chunk {
    std::int64_t seq = 0;
    std::int64_t t0_us = 0;
    std::vector<std::uint8_t> data;
  };
  // Ordered by seq; empty for an unknown recording or one without chunks.
  std::vector<Chunk> chunks(std::int64_t recording_id);

 private:
  Database& db_;
};

}  // namespace incise::db
