#include "curriculum/progress.h"

#include <algorithm>
#include <map>
#include <set>

#include "curriculum/proficiency.h"

namespace incise::curriculum {

bool attempt_passed(const AttemptRecord& attempt) {
  if (attempt.adjusted) return *attempt.adjusted;
  return !attempt.scores.empty() &&
         std::all_of(attempt.scores.begin(), attempt.scores.end(), [](bool p) { return p; });
}

std::vector<TaskProgress> curriculum_progress(const Curriculum& curriculum,
                                              const std::vector<AttemptRecord>& sessions) {
  std::map<std::string, std::vector<bool>> history;
  for (const AttemptRecord& s : sessions) {
    if (s.finished) history[s.task].push_back(attempt_passed(s));
  }
  std::set<std::string> mastered;
  for (const Module& module : curriculum.modules) {
    for (const Task& task : module.tasks) {
      if (task_mastered(task, history[task.key])) mastered.insert(task.key);
    }
  }
  std::vector<TaskProgress> out;
  for (const Module& module : curriculum.modules) {
    for (const Task& task : module.tasks) {
      const std::vector<bool>& h = history[task.key];
      TaskProgress p;
      p.key = task.key;
      p.module = module.name;
      p.attempts = static_cast<int>(h.size());
      p.passed_attempts = static_cast<int>(std::count(h.begin(), h.end(), true));
      p.consecutive_passes = consecutive_passes(h);
      p.required_passes = task.consecutive_passes_required;
      p.mastered = mastered.contains(task.key);
      for (const std::string& prerequisite : task.prerequisites) {
        if (!mastered.contains(prerequisite)) p.missing_prerequisites.push_back(prerequisite);
      }
      out.push_back(std::move(p));
    }
  }
  return out;
}

const TaskProgress* find_progress(const std::vector<TaskProgress>& progress,
                                  const std::string& task_key) {
  const auto it = std::find_if(progress.begin(), progress.end(),
                               [&](const TaskProgress& p) { return p.key == task_key; });
  return it == progress.end() ? nullptr : &*it;
}

std::string locked_reason(const Curriculum& curriculum, const TaskProgress& progress) {
  if (progress.unlocked()) return "";
  const auto name_of = [&](const std::string& key) {
    const Task* task = find_task(curriculum, key);
    return "\"" + (task != nullptr ? task->name : key) + "\"";
  };
  std::string missing;
  for (std::size_t i = 0; i < progress.missing_prerequisites.size(); ++i) {
    const bool last = i + 1 == progress.missing_prerequisites.size();
    missing += (i == 0 ? "" : last ? " and " : ", ") + name_of(progress.missing_prerequisites[i]);
  }
  return "task " + name_of(progress.key) + " is locked: master " + missing + " first";
}

std::string next_task(const std::vector<TaskProgress>& progress) {
  for (const TaskProgress& p : progress) {
    if (p.unlocked() && !p.mastered) return p.key;
  }
  return "";
}

}  // namespace incise::curriculum
