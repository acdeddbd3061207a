#pragma once
// Scoring at the end of a session: the curriculum computes the task's metrics
// from the recorded stream, and the results are stored as the session's scores.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "curriculum/curriculum.h"
#include "curriculum/metrics.h"
#include "curriculum/motion_metrics.h"
#include "curriculum/run_events.h"
#include "db/database.h"
#include "server/live/tick_record.h"
#include "sim/tools/damage_metrics.h"

namespace incise::server::live {

// Reads every chunk of the recording in order. Throws std::runtime_error naming the chunk if one
// is malformed.
std::vector<TickRecord> load_tick_records(db::Database& db, std::int64_t recording_id);

// The recorded stream as the metrics take it: one sample per tick at t = tick * tick_s.
std::vector<curriculum::ToolSample> tool_samples(const std::vector<TickRecord>& ticks,
                                                 double tick_s);

// One hand's recorded stream (hand 0, or 1 of a two-handed recording) as the motion metrics take
// it.
std::vector<curriculum::HandSample> hand_samples(const std::vector<TickRecord>& ticks,
                                                 double tick_s, int hand);

// Every metric of a recording: the basic ones, each hand's motion metrics (the second hand's
// keys end in "_left"), with two hands the bimanual ones, and the event metrics of the task's
// zones and forces (run_events.h). A task scores those it names.
std::vector<curriculum::MetricValue> session_metrics(const std::vector<TickRecord>& ticks,
                                                     double tick_s, const curriculum::Task& task);

// What the review page plots under a replay: the recording's events and its signals in bins of
// interval_s.
struct SessionReview {
  std::vector<curriculum::RunEvent> events;
  curriculum::Timeline timeline;
};
SessionReview review_session(const std::vector<TickRecord>& ticks, double tick_s,
                             const curriculum::Task& task, double interval_s);

// What the simulation measured during a live run that the recording does not hold
// (SimEngine::damage): its tissue damage, and a surgical scene's cuts against the marked line and
// the protected structures it cut (sim_never_events; score_session counts them as never events).
std::vector<curriculum::MetricValue> simulation_metrics(const sim::tools::DamageMetrics& damage);

// Computes the task's metrics from the recording, adds #simulation_values (simulation_metrics of
// the run; its sim_never_events add to never_events), and stores them as the session's scores
// (one transaction). Returns the results.
std::vector<curriculum::MetricResult> score_session(
    db::Database& db, std::int64_t session_id, std::int64_t recording_id,
    const curriculum::Task& task, double tick_s, std::int64_t now,
    std::span<const curriculum::MetricValue> simulation_values = {});

}  // namespace incise::server::live
