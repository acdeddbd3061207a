#include "curriculum/curriculum.h"

namespace incise::curriculum {

std::string_view threshold_op_symbol(ThresholdOp op) {
  return op == ThresholdOp::at_most ? "<=" : ">=";
}

bool Task::has_never_events() const {
  if (never_force_n > 0) return true;
  for (const ProtectedZone& z : protected_zones) {
    if (z.never) return true;
  }
  return false;
}

const Task* find_task(const Curriculum& curriculum, std::string_view key) {
  for (const Module& module : curriculum.modules) {
    for (const Task& task : module.tasks) {
      if (task.key == key) return &task;
    }
  }
  return nullptr;
}

}  // namespace incise::curriculum
