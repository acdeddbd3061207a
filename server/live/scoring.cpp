#include "server/live/scoring.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "curriculum/attempt_metrics.h"
#include "curriculum/number_text.h"
#include "db/recordings_repo.h"
#include "db/training_repo.h"
#include "server/live/sim_engine.h"

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

std::vector<curriculum::HandSample> hand_samples(const std::vector<TickRecord>& ticks,
                                                 double tick_s, int hand) {
  std::vector<curriculum::HandSample> samples;
  samples.reserve(ticks.size());
  for (const auto& r : ticks) {
    const devices::DeviceState& s = hand == 0 ? r.input : r.second.input;
    const float* f = hand == 0 ? r.force : r.second.force;
    samples.push_back({static_cast<double>(r.tick) * tick_s,
                       {s.position.x, s.position.y, s.position.z},
                       {s.orientation.w, s.orientation.x, s.orientation.y, s.orientation.z},
                       static_cast<double>(s.jaw),
                       {f[0], f[1], f[2]},
                       s.buttons});
  }
  return samples;
}

namespace {

bool two_handed(const std::vector<TickRecord>& ticks) {
  return !ticks.empty() && ticks.front().has_second;
}

// The recording's hands: the right (device 0) and, when it is two-handed, the left.
struct Hands {
  std::vector<curriculum::HandSample> right;
  std::vector<curriculum::HandSample> left;
};
Hands recorded_hands(const std::vector<TickRecord>& ticks, double tick_s) {
  Hands hands{hand_samples(ticks, tick_s, 0), {}};
  if (two_handed(ticks)) hands.left = hand_samples(ticks, tick_s, 1);
  return hands;
}

std::vector<curriculum::MetricValue> recorded_metrics(
    const std::vector<TickRecord>& ticks, double tick_s, const curriculum::Task& task,
    std::span<const curriculum::MetricValue> simulation_values) {
  const auto hands = recorded_hands(ticks, tick_s);
  return curriculum::attempt_metrics(task, hands.right, hands.left, simulation_values);
}

}  // namespace

std::vector<curriculum::MetricValue> session_metrics(const std::vector<TickRecord>& ticks,
                                                     double tick_s, const curriculum::Task& task) {
  return recorded_metrics(ticks, tick_s, task, {});
}

SessionReview review_session(const std::vector<TickRecord>& ticks, double tick_s,
                             const curriculum::Task& task, double interval_s) {
  const auto hands = recorded_hands(ticks, tick_s);
  return {curriculum::run_events(task, hands.right, hands.left),
          curriculum::run_timeline(task, hands.right, hands.left, interval_s)};
}

std::vector<curriculum::MetricValue> simulation_metrics(const sim::tools::DamageMetrics& damage) {
  const double on_target =
      damage.cut_area > 0 ? 1.0 - damage.cut_area_outside_target / damage.cut_area : 0.0;
  return {
      {"sim_damage_index", damage.damage_index, ""},
      {"sim_peak_strain", damage.peak_strain, ""},
      {"cut_area_m2", damage.cut_area, "m^2"},
      {"cut_on_line_m2", damage.cut_area - damage.cut_area_outside_target, "m^2"},
      {"cut_on_target_fraction", on_target, ""},
      {"cut_mean_distance_m", damage.cut_mean_distance, "m"},
      {"cut_max_distance_m", damage.cut_max_distance, "m"},
      {std::string(curriculum::kSimNeverEventsKey), damage.never_event ? 1.0 : 0.0, "count"},
  };
}

std::vector<curriculum::MetricResult> score_session(
    db::Database& db, std::int64_t session_id, std::int64_t recording_id,
    const curriculum::Task& task, double tick_s, std::int64_t now,
    std::span<const curriculum::MetricValue> simulation_values) {
  const auto values =
      recorded_metrics(load_tick_records(db, recording_id), tick_s, task, simulation_values);
  auto results = curriculum::score_attempt(task, values);
  std::vector<db::ScoreInput> scores;
  for (const auto& r : results) {
    // An undefined metric (the smoothness of a tool that never moved: NaN) fails; stored as 0.
    // With the threshold it was judged against, which the curriculum may change later.
    scores.push_back({r.key, std::isfinite(r.value) ? r.value : 0.0, r.unit, r.passed,
                      std::string(curriculum::threshold_op_symbol(r.threshold.op)),
                      r.threshold.value, r.criterion});
  }
  db::TrainingRepo(db).add_scores(session_id, scores, now);
  return results;
}

}  // namespace incise::server::live
