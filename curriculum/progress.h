#pragma once

// Where a trainee stands in a curriculum, from their sessions: per task the attempts, the current
// run of passes, whether it is mastered, and whether it is unlocked (every prerequisite mastered).
// The server enforces it (a locked task does not start) and the dashboard shows it; neither
// re-derives it.

#include <optional>
#include <string>
#include <vector>

#include "curriculum/curriculum.h"

namespace incise::curriculum {

// One session of the trainee, as the record keeps it.
struct AttemptRecord {
  std::string task;       // the task's key
  bool finished = false;  // only a finished session is an attempt (not a running or aborted one)
  // Whether each of its scored metrics passed; none: it was not scored.
  std::vector<bool> scores;
  std::optional<bool> adjusted;  // an instructor's adjustment, if any
};

// Whether a finished attempt passed: the instructor's adjustment if there is one, else true when
// it was scored and every score passed (an unscored attempt does not pass).
bool attempt_passed(const AttemptRecord& attempt);

struct TaskProgress {
  std::string key;
  std::string module;  // the module's name
  int attempts = 0;
  int passed_attempts = 0;
  int consecutive_passes = 0;  // the current run (proficiency.h)
  int required_passes = 1;
  bool mastered = false;
  // The prerequisites not yet mastered, in the task's order; empty: the task is unlocked.
  std::vector<std::string> missing_prerequisites;
  bool unlocked() const { return missing_prerequisites.empty(); }
};

// Every task of the curriculum in its order, from the trainee's sessions (oldest first; sessions
// of tasks the curriculum does not have are ignored). A task is mastered once
// consecutive_passes_required attempts in a row have passed (task_mastered; it stays mastered
// after a later failure, and whatever its prerequisites); it is unlocked when all its
// prerequisites are mastered.
std::vector<TaskProgress> curriculum_progress(const Curriculum& curriculum,
                                              const std::vector<AttemptRecord>& sessions);

// The entry of task_key in progress, or nullptr.
const TaskProgress* find_progress(const std::vector<TaskProgress>& progress,
                                  const std::string& task_key);

// The task to work on next: the first of the curriculum's order that is unlocked and not yet
// mastered, "" when every task is mastered (or none is unlocked). progress: curriculum_progress.
std::string next_task(const std::vector<TaskProgress>& progress);

// Why the task may not start, "" if it may: "task \"Cut along the marked line\" is locked:
// master \"Palpation\" first" (names from the curriculum, in the prerequisites' order).
std::string locked_reason(const Curriculum& curriculum, const TaskProgress& progress);

}  // namespace incise::curriculum
