#pragma once
// Motion and force metrics of a recorded run, and scoring them against a task's thresholds.
// Pure functions over plain sample streams (docs/architecture.md: curriculum takes no input from
// the simulation other than what was recorded), so a live session, a replay and a test compute
// the same numbers.
#include <array>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "curriculum/curriculum.h"

namespace incise::curriculum {

// One sample of a recorded run, at the simulation's tick rate (e.g. 500 Hz).
struct ToolSample {
  double t_s = 0;                   // since the start of the run [s], non-decreasing
  std::array<double, 3> tip_m{};    // tool tip position [m]
  std::array<double, 3> force_n{};  // force on the tool [N]
};

// One computed metric. Its name, display unit and definition are in the catalogue
// (metric_catalogue.h), keyed the same.
struct MetricValue {
  std::string key;  // "completion_time_s", "path_length_m", "peak_force_n", "rms_force_n",
                    // "contact_time_s"
  double value = 0;
  std::string unit;  // "s", "m", "N"

  bool operator==(const MetricValue&) const = default;
};

// Above this force [N] the tool counts as touching tissue (contact_time_s).
inline constexpr double kContactForceN = 1e-3;

// The five basic metrics of a run of #samples samples, in this order:
//   completion_time_s  last t - first t [s]; 0 for fewer than 2 samples
//   path_length_m      sum over i of |tip_{i+1} - tip_i| [m]
//   peak_force_n       max over i of |force_i| [N]; 0 for no samples
//   rms_force_n        sqrt(integral of |force|^2 dt / duration) [N], the integral by the trapezoid
//                      rule over the sample times; 0 when the run has no duration
//   contact_time_s     sum of t_{i+1} - t_i over the samples i with |force_i| > kContactForceN [s]:
//                      proof that the tissue was actually touched (an idle run scores 0)
// Time-weighting makes the RMS independent of the sampling rate and of uneven tick spacing;
// samples with equal times add path length but no RMS weight.
// Throws std::invalid_argument for a non-finite time, position or force, or a time smaller than
// the previous sample's, naming the sample index, e.g. "sample 7: t_s 0.012 is before the
// previous sample's 0.014".
std::vector<MetricValue> basic_metrics(std::span<const ToolSample> samples);

// How one metric the task requires fared in one attempt.
struct MetricResult {
  std::string key;
  double value = 0;  // the measured value; 0 when not measured
  std::string unit;  // the measured value's unit; the requirement's when not measured
  Threshold threshold;
  bool passed = false;
  bool measured = true;    // false when the task asks for a metric the computation did not report
                           // (then passed = false)
  bool criterion = false;  // a completion criterion (Task::completion), not a threshold
};

// The metric counting never events (run_events.h).
inline constexpr std::string_view kNeverEventsKey = "never_events";

// The metrics the completion criteria are scored on (Task::completion), in this order, each only
// when set:
//   tissue_contact_s >= min_contact_s       [s]   every tool's time on the tissue, added up
//   targets_fraction >= 1                         when all_targets
//   cut_on_line_m2   >= min_cut_on_line_m2  [m^2] the area cut inside the marked line's band
std::vector<MetricRequirement> completion_requirements(const Task& task);

// The metrics an attempt at the task is scored on: the completion criteria first
// (completion_requirements), then the task's metrics in their order, and when the task can have
// never events (Task::has_never_events) but does not name kNeverEventsKey, one more for
// never_events <= 0 at the end: a never event fails the attempt outright.
std::vector<MetricRequirement> scored_requirements(const Task& task);

// One result per scored requirement (scored_requirements), in that order; the criteria's results
// have criterion set. For each requirement the
// first value in #values with the same key is scored (meets_threshold: the boundary passes, NaN
// fails); values the task does not ask for are ignored.
std::vector<MetricResult> score_attempt(const Task& task, std::span<const MetricValue> values);

// True if every metric passed and there was at least one: an attempt scored on nothing proves
// nothing, so it never counts towards mastery.
bool attempt_passed(std::span<const MetricResult> results);

}  // namespace incise::curriculum
