#include "curriculum/proficiency.h"

namespace incise::curriculum {

bool meets_threshold(const Threshold& threshold, double value) {
  // Written so that NaN compares false either way.
  return threshold.op == ThresholdOp::at_most ? value <= threshold.value : value >= threshold.value;
}

bool attempt_passes(const Task& task, const std::map<std::string, double>& metric_values) {
  for (const MetricRequirement& metric : task.metrics) {
    const auto value = metric_values.find(metric.key);
    if (value == metric_values.end() || !meets_threshold(metric.threshold, value->second)) {
      return false;
    }
  }
  return true;
}

int consecutive_passes(const std::vector<bool>& attempt_passed) {
  int count = 0;
  for (auto it = attempt_passed.rbegin(); it != attempt_passed.rend() && *it; ++it)
    ++count;
  return count;
}

bool task_mastered(const Task& task, const std::vector<bool>& attempt_passed) {
  int run = 0;
  for (const bool passed : attempt_passed) {
    run = passed ? run + 1 : 0;
    if (run >= task.consecutive_passes_required) return true;
  }
  return false;
}

}  // namespace incise::curriculum
