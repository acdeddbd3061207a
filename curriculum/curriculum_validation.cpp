#include "curriculum/curriculum_validation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "curriculum/metric_catalogue.h"
#include "curriculum/metrics.h"
#include "curriculum/number_text.h"

namespace incise::curriculum {
namespace {

std::string member(const std::string& path, std::string_view key) {
  return path.empty() ? std::string(key) : path + "." + std::string(key);
}

std::string element(const std::string& path, std::size_t index) {
  return path + "[" + std::to_string(index) + "]";
}

void require_key(const std::string& path, const std::string& key) {
  if (!is_valid_key(key)) {
    throw CurriculumError(path,
                          "must be a key: a lowercase letter, then lowercase letters, "
                          "digits or '_' (got \"" +
                              key + "\")");
  }
}

void require_text(const std::string& path, const std::string& text) {
  if (text.empty()) throw CurriculumError(path, "must not be empty");
}

// Rejects empty entries and repeats in a list of names (tools, prerequisites).
void require_distinct_names(const std::string& path, const std::vector<std::string>& names) {
  std::set<std::string> seen;
  for (std::size_t i = 0; i < names.size(); ++i) {
    require_text(element(path, i), names[i]);
    if (!seen.insert(names[i]).second) {
      throw CurriculumError(element(path, i), "duplicate entry \"" + names[i] + "\"");
    }
  }
}

// A zone or target at #path; its name must be new in #names (name -> path of its first use),
// since events and results name zones and targets alike.
void check_zone(const Zone& zone, const std::string& path,
                std::map<std::string, std::string>& names) {
  const std::string name_path = member(path, "name");
  require_text(name_path, zone.name);
  const auto [first, inserted] = names.emplace(zone.name, path);
  if (!inserted) {
    throw CurriculumError(name_path, "duplicate zone or target name \"" + zone.name +
                                         "\" (first at " + first->second + ")");
  }
  for (std::size_t i = 0; i < zone.center_m.size(); ++i) {
    if (!std::isfinite(zone.center_m[i])) {
      throw CurriculumError(element(member(path, "center_m"), i), "must be a finite number");
    }
  }
  if (!std::isfinite(zone.radius_m) || zone.radius_m <= 0) {
    throw CurriculumError(member(path, "radius_m"), "must be a finite number above 0");
  }
}

void check_forces(const Task& task, const std::string& path) {
  if (!std::isfinite(task.safe_force_n) || task.safe_force_n <= 0) {
    throw CurriculumError(member(path, "safe_force_n"), "must be a finite number above 0");
  }
  const std::string never_path = member(path, "never_force_n");
  if (!std::isfinite(task.never_force_n) || task.never_force_n < 0) {
    throw CurriculumError(never_path, "must be a finite number, 0 (no limit) or more");
  }
  // A never limit at or below the safe force would fail attempts that never overloaded tissue.
  if (task.never_force_n > 0 && task.never_force_n <= task.safe_force_n) {
    throw CurriculumError(never_path, "must be 0 (no limit) or above safe_force_n " +
                                          shortest_text(task.safe_force_n));
  }
}

// The criteria are finite and not negative, all_targets has targets to reach, and no metric
// threshold repeats a criterion's metric (a result holds one value per key).
void check_completion(const Task& task, const std::string& path) {
  const std::string completion_path = member(path, "completion");
  const Completion& c = task.completion;
  for (const auto& [name, value] : {std::pair("min_contact_s", c.min_contact_s),
                                    std::pair("min_cut_on_line_m2", c.min_cut_on_line_m2)}) {
    if (!std::isfinite(value) || value < 0) {
      throw CurriculumError(member(completion_path, name), "must be a finite number, 0 or more");
    }
  }
  if (c.all_targets && task.targets.empty()) {
    throw CurriculumError(member(completion_path, "all_targets"),
                          "needs targets: the task has none to reach");
  }
  for (const MetricRequirement& criterion : completion_requirements(task)) {
    for (std::size_t m = 0; m < task.metrics.size(); ++m) {
      if (task.metrics[m].key != criterion.key) continue;
      throw CurriculumError(member(element(member(path, "metrics"), m), "key"),
                            "\"" + criterion.key + "\" is already a completion criterion");
    }
  }
}

struct TaskRef {
  const Task* task;
  std::string path;  // "modules[i].tasks[j]"
};

void check_task(const Task& task, const std::string& path) {
  require_key(member(path, "key"), task.key);
  require_text(member(path, "name"), task.name);
  require_text(member(path, "scene"), task.scene);
  if (!task.station_kind.empty()) require_key(member(path, "station_kind"), task.station_kind);
  if (!task.material.empty()) require_text(member(path, "material"), task.material);
  require_distinct_names(member(path, "tools"), task.tools);
  const std::string metrics_path = member(path, "metrics");
  if (task.metrics.empty()) throw CurriculumError(metrics_path, "must list at least one metric");
  std::set<std::string> metric_keys;
  for (std::size_t m = 0; m < task.metrics.size(); ++m) {
    const MetricRequirement& metric = task.metrics[m];
    const std::string metric_path = element(metrics_path, m);
    require_key(member(metric_path, "key"), metric.key);
    if (!metric_keys.insert(metric.key).second) {
      throw CurriculumError(member(metric_path, "key"),
                            "duplicate metric key \"" + metric.key + "\"");
    }
    if (!std::isfinite(metric.threshold.value)) {
      throw CurriculumError(member(member(metric_path, "threshold"), "value"),
                            "must be a finite number");
    }
    // Within the values the metric can take (metric_catalogue.h): a negative time or a share
    // above 1 is a typing error that would pass or fail every attempt. Keys the catalogue does
    // not know are left to score_attempt (unmeasured: failed).
    if (const auto info = find_metric(metric.key);
        info && (metric.threshold.value < info->min || metric.threshold.value > info->max)) {
      const std::string unit = info->unit.empty() || info->unit == "count" ? "" : " " + info->unit;
      throw CurriculumError(
          member(member(metric_path, "threshold"), "value"),
          std::isinf(info->max)
              ? "must be " + shortest_text(info->min) + unit + " or more for " + metric.key
              : "must be from " + shortest_text(info->min) + " to " + shortest_text(info->max) +
                    unit + " for " + metric.key);
    }
    // A never event fails the attempt outright (metrics.h): no task may tolerate one.
    if (metric.key == kNeverEventsKey &&
        (metric.threshold.op != ThresholdOp::at_most || metric.threshold.value != 0)) {
      throw CurriculumError(member(metric_path, "threshold"),
                            "never_events must be \"<=\" 0: a never event fails the attempt");
    }
  }
  if (task.consecutive_passes_required < 1 ||
      task.consecutive_passes_required > max_consecutive_passes) {
    throw CurriculumError(member(path, "consecutive_passes_required"),
                          "must be an integer from 1 to " + std::to_string(max_consecutive_passes));
  }
  require_distinct_names(member(path, "prerequisites"), task.prerequisites);
  std::map<std::string, std::string> zone_names;
  for (std::size_t z = 0; z < task.protected_zones.size(); ++z) {
    check_zone(task.protected_zones[z].zone, element(member(path, "protected_zones"), z),
               zone_names);
  }
  for (std::size_t t = 0; t < task.targets.size(); ++t)
    check_zone(task.targets[t], element(member(path, "targets"), t), zone_names);
  check_forces(task, path);
  check_completion(task, path);
  if (task.portal_m) {
    for (std::size_t i = 0; i < task.portal_m->size(); ++i) {
      if (!std::isfinite((*task.portal_m)[i])) {
        throw CurriculumError(element(member(path, "portal_m"), i), "must be a finite number");
      }
    }
  }
}

// Depth-first search along prerequisite edges; a task met again while still on the stack closes
// a cycle. Throws at the prerequisite entry that closes it.
class CycleFinder {
 public:
  explicit CycleFinder(const std::map<std::string, TaskRef>& tasks) : tasks_(tasks) {}

  void visit(const std::string& key) {
    if (finished_.count(key) > 0) return;
    stack_.push_back(key);
    const TaskRef& ref = tasks_.at(key);
    for (std::size_t p = 0; p < ref.task->prerequisites.size(); ++p) {
      const std::string& next = ref.task->prerequisites[p];
      const auto on_stack = std::find(stack_.begin(), stack_.end(), next);
      if (on_stack != stack_.end()) {
        std::string cycle;
        for (auto it = on_stack; it != stack_.end(); ++it)
          cycle += *it + " -> ";
        throw CurriculumError(element(member(ref.path, "prerequisites"), p),
                              "prerequisite cycle: " + cycle + next);
      }
      visit(next);
    }
    stack_.pop_back();
    finished_.insert(key);
  }

 private:
  const std::map<std::string, TaskRef>& tasks_;
  std::vector<std::string> stack_;
  std::set<std::string> finished_;
};

}  // namespace

bool is_valid_key(std::string_view key) {
  if (key.empty() || key.front() < 'a' || key.front() > 'z') return false;
  for (const char c : key) {
    const bool allowed = (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
    if (!allowed) return false;
  }
  return true;
}

void validate(const Curriculum& curriculum) {
  require_text("name", curriculum.name);
  if (curriculum.modules.empty()) {
    throw CurriculumError("modules", "must list at least one module");
  }

  std::set<std::string> module_keys;
  std::map<std::string, TaskRef> tasks;  // by key
  std::vector<std::string> task_order;   // document order, so that errors are reproducible
  for (std::size_t i = 0; i < curriculum.modules.size(); ++i) {
    const Module& module = curriculum.modules[i];
    const std::string path = element("modules", i);
    require_key(member(path, "key"), module.key);
    if (!module_keys.insert(module.key).second) {
      throw CurriculumError(member(path, "key"), "duplicate module key \"" + module.key + "\"");
    }
    require_text(member(path, "name"), module.name);
    if (module.tasks.empty()) {
      throw CurriculumError(member(path, "tasks"), "must list at least one task");
    }
    for (std::size_t j = 0; j < module.tasks.size(); ++j) {
      const Task& task = module.tasks[j];
      const std::string task_path = element(member(path, "tasks"), j);
      check_task(task, task_path);
      const auto [first, inserted] = tasks.emplace(task.key, TaskRef{&task, task_path});
      if (!inserted) {
        throw CurriculumError(
            member(task_path, "key"),
            "duplicate task key \"" + task.key + "\" (first at " + first->second.path + ")");
      }
      task_order.push_back(task.key);
    }
  }

  for (const std::string& key : task_order) {
    const TaskRef& ref = tasks.at(key);
    for (std::size_t p = 0; p < ref.task->prerequisites.size(); ++p) {
      const std::string& prerequisite = ref.task->prerequisites[p];
      if (tasks.count(prerequisite) == 0) {
        throw CurriculumError(element(member(ref.path, "prerequisites"), p),
                              "unknown task \"" + prerequisite + "\"");
      }
    }
  }

  CycleFinder cycles(tasks);
  for (const std::string& key : task_order)
    cycles.visit(key);
}

}  // namespace incise::curriculum
