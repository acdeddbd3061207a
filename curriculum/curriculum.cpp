#include "curriculum/curriculum.h"

namespace incise::curriculum {

std::string_view threshold_op_symbol(ThresholdOp op) {
  return op == ThresholdOp::at_most ? "<=" : ">=";
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
