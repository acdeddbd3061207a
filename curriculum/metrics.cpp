#include "curriculum/metrics.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "curriculum/proficiency.h"

namespace incise::curriculum {

namespace {

double norm(const std::array<double, 3>& v) {
  return std::hypot(v[0], v[1], v[2]);
}

double distance(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return std::hypot(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
}

bool all_finite(const std::array<double, 3>& v) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

[[noreturn]] void bad_sample(std::size_t index, std::string_view reason) {
  std::ostringstream message;
  message << "sample " << index << ": " << reason;
  throw std::invalid_argument(message.str());
}

// Checked before any arithmetic, so that a NaN cannot hide inside a max or a sum.
void check_samples(std::span<const ToolSample> samples) {
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const ToolSample& s = samples[i];
    if (!std::isfinite(s.t_s)) bad_sample(i, "t_s is not finite");
    if (!all_finite(s.tip_m)) bad_sample(i, "tip_m is not finite");
    if (!all_finite(s.force_n)) bad_sample(i, "force_n is not finite");
    if (i > 0 && s.t_s < samples[i - 1].t_s) {
      std::ostringstream reason;
      reason.precision(17);
      reason << "t_s " << s.t_s << " is before the previous sample's " << samples[i - 1].t_s;
      bad_sample(i, reason.str());
    }
  }
}

}  // namespace

std::vector<MetricValue> basic_metrics(std::span<const ToolSample> samples) {
  check_samples(samples);

  double path_length = 0;
  double peak_force = 0;
  double force_squared_integral = 0;  // [N^2 s]
  double previous_force_squared = 0;
  double contact_time = 0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const double force = norm(samples[i].force_n);
    const double force_squared = force * force;
    peak_force = std::max(peak_force, force);
    if (i > 0) {
      path_length += distance(samples[i - 1].tip_m, samples[i].tip_m);
      const double dt = samples[i].t_s - samples[i - 1].t_s;
      force_squared_integral += 0.5 * dt * (previous_force_squared + force_squared);
      if (previous_force_squared > kContactForceN * kContactForceN) contact_time += dt;
    }
    previous_force_squared = force_squared;
  }
  const double duration = samples.size() < 2 ? 0.0 : samples.back().t_s - samples.front().t_s;
  const double rms_force = duration > 0 ? std::sqrt(force_squared_integral / duration) : 0.0;

  return {
      {"completion_time_s", duration, "s"},  {"path_length_m", path_length, "m"},
      {"peak_force_n", peak_force, "N"},     {"rms_force_n", rms_force, "N"},
      {"contact_time_s", contact_time, "s"},
  };
}

std::vector<MetricRequirement> completion_requirements(const Task& task) {
  const Completion& c = task.completion;
  std::vector<MetricRequirement> criteria;
  if (c.min_contact_s > 0)
    criteria.push_back({"tissue_contact_s", {ThresholdOp::at_least, c.min_contact_s}, "s"});
  if (c.all_targets) criteria.push_back({"targets_fraction", {ThresholdOp::at_least, 1.0}, ""});
  if (c.min_cut_on_line_m2 > 0)
    criteria.push_back({"cut_on_line_m2", {ThresholdOp::at_least, c.min_cut_on_line_m2}, "m^2"});
  return criteria;
}

std::vector<MetricRequirement> scored_requirements(const Task& task) {
  std::vector<MetricRequirement> requirements = completion_requirements(task);
  requirements.insert(requirements.end(), task.metrics.begin(), task.metrics.end());
  const bool names_never =
      std::any_of(requirements.begin(), requirements.end(),
                  [](const MetricRequirement& r) { return r.key == kNeverEventsKey; });
  if (task.has_never_events() && !names_never) {
    requirements.push_back({std::string(kNeverEventsKey), {ThresholdOp::at_most, 0.0}, "count"});
  }
  return requirements;
}

std::vector<MetricResult> score_attempt(const Task& task, std::span<const MetricValue> values) {
  const auto requirements = scored_requirements(task);
  const std::size_t criteria = completion_requirements(task).size();
  std::vector<MetricResult> results;
  results.reserve(requirements.size());
  for (const MetricRequirement& requirement : requirements) {
    const auto found = std::find_if(values.begin(), values.end(),
                                    [&](const MetricValue& v) { return v.key == requirement.key; });
    MetricResult result;
    result.key = requirement.key;
    result.threshold = requirement.threshold;
    result.criterion = results.size() < criteria;
    if (found == values.end()) {
      result.unit = requirement.unit;
      result.measured = false;
      result.passed = false;
    } else {
      result.value = found->value;
      result.unit = found->unit;
      result.passed = meets_threshold(requirement.threshold, found->value);
    }
    results.push_back(std::move(result));
  }
  return results;
}

bool attempt_passed(std::span<const MetricResult> results) {
  return !results.empty() && std::all_of(results.begin(), results.end(),
                                         [](const MetricResult& r) { return r.passed; });
}

}  // namespace incise::curriculum
