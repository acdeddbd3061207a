#include "server/live/scoring.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

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

}  // namespace

std::vector<curriculum::MetricValue> session_metrics(const std::vector<TickRecord>& ticks,
                                                     double tick_s, const curriculum::Task& task) {
  // The basic metrics first: where a motion metric has the same key, score_attempt takes the
  // first.
  auto values = curriculum::basic_metrics(tool_samples(ticks, tick_s));
  const auto right = hand_samples(ticks, tick_s, 0);
  for (auto& v : curriculum::hand_metrics(right))
    values.push_back(std::move(v));
  std::vector<curriculum::HandSample> left;
  if (two_handed(ticks)) {
    left = hand_samples(ticks, tick_s, 1);
    for (auto v : curriculum::hand_metrics(left)) {
      v.key += "_left";
      v.definition += " (Left hand.)";
      values.push_back(std::move(v));
    }
    for (auto& v : curriculum::bimanual_metrics(right, left))
      values.push_back(std::move(v));
  }
  const auto events = curriculum::run_events(task, right, left);
  for (auto& v : curriculum::event_metrics(task, right, left, events))
    values.push_back(std::move(v));
  return values;
}

SessionReview review_session(const std::vector<TickRecord>& ticks, double tick_s,
                             const curriculum::Task& task, double interval_s) {
  const auto right = hand_samples(ticks, tick_s, 0);
  std::vector<curriculum::HandSample> left;
  if (two_handed(ticks)) left = hand_samples(ticks, tick_s, 1);
  return {curriculum::run_events(task, right, left),
          curriculum::run_timeline(task, right, left, interval_s)};
}

std::vector<curriculum::MetricValue> simulation_metrics(const sim::tools::DamageMetrics& damage) {
  const double on_target =
      damage.cut_area > 0 ? 1.0 - damage.cut_area_outside_target / damage.cut_area : 0.0;
  return {
      {"sim_damage_index", damage.damage_index, "",
       "Share of the tissue's volume the simulation strained beyond its damage threshold (max "
       "principal Green strain; " +
           curriculum::shortest_text(sim::surgery::BlockSceneOptions{}.strain_threshold) +
           " in the palpation block)."},
      {"sim_peak_strain", damage.peak_strain, "",
       "Largest principal Green strain of any tissue element in the simulation."},
      {"cut_area_m2", damage.cut_area, "m^2",
       "Area the scalpel cut (rest area of the cut surface, one side); surgical scenes."},
      {"cut_on_target_fraction", on_target, "",
       "Share of the cut area within the marked line's band (0 without a cut); surgical scenes."},
      {"cut_mean_distance_m", damage.cut_mean_distance, "m",
       "Area-weighted mean distance of the cut surface from the marked line; surgical scenes."},
      {"cut_max_distance_m", damage.cut_max_distance, "m",
       "Largest distance of any cut face from the marked line; surgical scenes."},
      {"sim_never_events", damage.never_event ? 1.0 : 0.0, "count",
       "Protected structures the scalpel cut (a never event; also counted in never_events)."},
  };
}

std::vector<curriculum::MetricValue> metric_catalogue() {
  // The metrics of a short two-handed recording: every key a task may score, with its unit and
  // definition exactly as scoring reports them (the values are of no interest).
  std::vector<TickRecord> ticks(8);
  for (std::uint32_t i = 0; i < ticks.size(); ++i) {
    ticks[i].tick = i;
    ticks[i].input.position = {0.001 * i * i, 0, 0};
    ticks[i].has_second = true;
    ticks[i].second.input.position = {0, 0.001 * i, 0};
  }
  // A task with a portal, so that the depth along the shaft is reported too.
  curriculum::Task every_metric;
  every_metric.portal_m = std::array<double, 3>{0, 0, 0};
  auto values = session_metrics(ticks, 0.002, every_metric);
  for (auto& v : simulation_metrics({}))
    values.push_back(std::move(v));
  // Where a key comes twice (the basic metrics and a hand's), the first is the one scored.
  std::vector<curriculum::MetricValue> catalogue;
  for (auto& v : values) {
    const bool seen = std::any_of(catalogue.begin(), catalogue.end(),
                                  [&](const curriculum::MetricValue& c) { return c.key == v.key; });
    if (seen) continue;
    v.value = 0;
    catalogue.push_back(std::move(v));
  }
  return catalogue;
}

std::vector<curriculum::MetricResult> score_session(
    db::Database& db, std::int64_t session_id, std::int64_t recording_id,
    const curriculum::Task& task, double tick_s, std::int64_t now,
    std::span<const curriculum::MetricValue> simulation_values) {
  auto values = session_metrics(load_tick_records(db, recording_id), tick_s, task);
  values.insert(values.end(), simulation_values.begin(), simulation_values.end());
  // A protected structure the simulation saw cut is a never event like one the recording shows.
  const auto value_of = [&](std::string_view key) {
    return std::find_if(values.begin(), values.end(),
                        [&](const curriculum::MetricValue& v) { return v.key == key; });
  };
  const auto never = value_of("never_events");
  const auto cut_never = value_of("sim_never_events");
  if (never != values.end() && cut_never != values.end()) never->value += cut_never->value;
  auto results = curriculum::score_attempt(task, values);
  std::vector<db::ScoreInput> scores;
  for (const auto& r : results) {
    // An undefined metric (the smoothness of a tool that never moved: NaN) fails; stored as 0.
    // With the threshold it was judged against, which the curriculum may change later.
    scores.push_back({r.key, std::isfinite(r.value) ? r.value : 0.0, r.unit, r.passed,
                      std::string(curriculum::threshold_op_symbol(r.threshold.op)),
                      r.threshold.value});
  }
  db::TrainingRepo(db).add_scores(session_id, scores, now);
  return results;
}

}  // namespace incise::server::live
