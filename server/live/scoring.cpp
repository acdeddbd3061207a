#include "server/live/scoring.h"

#include <stdexcept>

#include "db/recordings_repo.h"
#include "db/training_repo.h"

namespace incise::server::live {

std::vector<TickRecord> load_tick_records(db::Database& db, std::int64_t recording_id) {
  std::vector<TickRecord> ticks;
  for (const auto& chunk : db::RecordingsRepo(db).chunks(recording_id)) {
    const auto error = decode_tick_records(chunk.data, ticks);
    if (!error.empty()) {
      throw std::runtime_error("recording " + std::to_string(recording_id) + " chunk " +
                               std::to_string(chunk.seq) + ": " + error);
    }
  }
  return ticks;
}

std::vector<curriculum::ToolSample> tool_samples(const std::vector<TickRecord>& ticks,
                                                 double tick_s) {
  std::vector<curriculum::ToolSample> samples;
  samples.reserve(ticks.size());
  for (const auto& r : ticks) {
    const auto& p = r.input.position;
    samples.push_back({static_cast<double>(r.tick) * tick_s,
                       {p.x, p.y, p.z},
                       {r.force[0], r.force[1], r.force[2]}});
  }
  return samples;
}

std::vector<curriculum::MetricResult> score_session(db::Database& db, std::int64_t session_id,
                                                    std::int64_t recording_id,
                                                    const curriculum::Task& task, double tick_s,
                                                    std::int64_t now) {
  const auto samples = tool_samples(load_tick_records(db, recording_id), tick_s);
  const auto values = curriculum::basic_metrics(samples);
  auto results = curriculum::score_attempt(task, values);
  std::vector<db::ScoreInput> scores;
  for (const auto& r : results)
    scores.push_back({r.key, r.value, r.unit, r.passed});
  db::TrainingRepo(db).add_scores(session_id, scores, now);
  return results;
}

}  // namespace incise::server::live
