#pragma once

#include <map>
#include <string>
#include <vector>

#include "curriculum/curriculum.h"

namespace incise::curriculum {

// Proficiency-based progression: a trainee masters a task by meeting every metric threshold in
// N consecutive attempts (N = Task::consecutive_passes_required), so that one lucky run does not
// count, and any failure starts the count again.

// True if value satisfies the threshold; a value equal to the threshold passes. NaN never passes.
bool meets_threshold(const Threshold& threshold, double value);

// True if every metric of the task meets its threshold. metric_values: the attempt's measured
// values by metric key, in each metric's unit; a metric of the task that is missing fails the
// attempt, values the task does not score are ignored.
bool attempt_passes(const Task& task, const std::map<std::string, double>& metric_values);

// Number of passing attempts at the end of attempt_passed (oldest first), i.e. the current run.
int consecutive_passes(const std::vector<bool>& attempt_passed);

// True once consecutive_passes_required attempts in a row have passed, at any point of
// attempt_passed (oldest first): proficiency once shown is kept, so a later failure (practice after
// moving on) neither un-masters the task nor locks again what it unlocked; the current run
// (consecutive_passes) starts again.
bool task_mastered(const Task& task, const std::vector<bool>& attempt_passed);

}  // namespace incise::curriculum
