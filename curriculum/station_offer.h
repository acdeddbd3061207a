#pragma once
// Which tasks a station offers: a task runs only at a station of the kind it needs (its devices
// and scenes), and a trainee starts only what their progress has unlocked. The server refuses the
// rest (POST /api/sessions) and lists only these (GET /api/stations/{id}/tasks), so the dashboard
// shows what may start and copies no rule.

#include <string>
#include <string_view>
#include <vector>

#include "curriculum/curriculum.h"
#include "curriculum/progress.h"

namespace incise::curriculum {

// True if a station of #station_kind can run the task: the task names no kind, or the same one.
bool station_fits(const Task& task, std::string_view station_kind);

// Why the station cannot run the task, "" if it can: "task \"Palpation\" needs a bench station;
// Surgical station is a laparoscopy station" ("... declares no kind" for a station without one).
std::string station_misfit(const Task& task, std::string_view station_name,
                           std::string_view station_kind);

// A task a station offers, with why it may not start yet ("" when it may).
struct TaskOffer {
  const Task* task = nullptr;  // into the curriculum given
  std::string module;          // the module's name
  std::string locked_reason;   // locked_reason of the trainee's progress
};

// The tasks of #curriculum that fit #station_kind, in the curriculum's order. With #progress (a
// trainee's, curriculum_progress of the same curriculum) each carries its lock; without (an
// instructor or admin, who may run any task) none is locked.
std::vector<TaskOffer> station_offer(const Curriculum& curriculum, std::string_view station_kind,
                                     const std::vector<TaskProgress>* progress);

}  // namespace incise::curriculum
