#pragma once
// The metrics of one attempt, composed in one place: what a live session scores, what a replay's
// review shows and what a benchmark measures are the same list.
#include <span>
#include <vector>

#include "curriculum/curriculum.h"
#include "curriculum/metrics.h"
#include "curriculum/motion_metrics.h"

namespace incise::curriculum {

// The metric counting the protected structures the simulation saw cut (a never event the
// recording cannot show: the simulation reports it, see simulation_metrics in the server).
inline constexpr std::string_view kSimNeverEventsKey = "sim_never_events";

// Every metric of an attempt at #task, in this order:
//   the basic metrics of the right hand (basic_metrics: time, path, forces, contact_time_s);
//   the right hand's motion metrics (hand_metrics; a key the basic metrics already have is
//   reported twice, and score_attempt takes the first);
//   with a left hand, its motion metrics with keys ending in "_left", then the bimanual ones;
//   the event metrics of the task's zones, targets and forces (event_metrics);
//   then #simulation, what the simulation measured that the recording does not hold. Its
//   kSimNeverEventsKey adds to never_events: a structure cut is a never event like one entered.
// #left is empty for a one-handed attempt. Throws std::invalid_argument as the metrics do for
// malformed samples.
std::vector<MetricValue> attempt_metrics(const Task& task, std::span<const HandSample> right,
                                         std::span<const HandSample> left,
                                         std::span<const MetricValue> simulation = {});

}  // namespace incise::curriculum
