#include "curriculum/attempt_metrics.h"

#include <algorithm>
#include <string>
#include <utility>

#include "curriculum/run_events.h"

namespace incise::curriculum {

std::vector<MetricValue> attempt_metrics(const Task& task, std::span<const HandSample> right,
                                         std::span<const HandSample> left,
                                         std::span<const MetricValue> simulation) {
  std::vector<ToolSample> tool;
  tool.reserve(right.size());
  for (const HandSample& s : right)
    tool.push_back({s.t_s, s.tip_m, s.force_n});
  auto values = basic_metrics(tool);
  for (auto& v : hand_metrics(right))
    values.push_back(std::move(v));
  if (!left.empty()) {
    for (auto v : hand_metrics(left)) {
      v.key += "_left";
      values.push_back(std::move(v));
    }
    for (auto& v : bimanual_metrics(right, left))
      values.push_back(std::move(v));
  }
  const auto events = run_events(task, right, left);
  for (auto& v : event_metrics(task, right, left, events))
    values.push_back(std::move(v));
  values.insert(values.end(), simulation.begin(), simulation.end());

  const auto value_of = [&](std::string_view key) {
    return std::find_if(values.begin(), values.end(),
                        [&](const MetricValue& v) { return v.key == key; });
  };
  const auto never = value_of(kNeverEventsKey);
  const auto cut_never = value_of(kSimNeverEventsKey);
  if (never != values.end() && cut_never != values.end()) never->value += cut_never->value;
  return values;
}

}  // namespace incise::curriculum
