#pragma once

#include <string_view>

#include "curriculum/curriculum.h"
#include "curriculum/curriculum_error.h"

namespace incise::curriculum {

// Upper bound on Task::consecutive_passes_required: anything larger is a typing error, not a
// training plan.
constexpr int max_consecutive_passes = 1000;

// True for a key: a lowercase letter, then lowercase letters, digits or '_' ("peak_force_n").
// Keys end up in URLs, database rows and metric streams, so they are kept plain.
bool is_valid_key(std::string_view key);

// Checks what the types alone cannot say, and throws CurriculumError for the first problem, in
// three passes: each value on its own in document order (non-empty names, key syntax, unique
// module keys, task keys unique across the whole curriculum, unique metric keys per task, finite
// thresholds, 1 <= consecutive_passes_required <= max_consecutive_passes); then every
// prerequisite names an existing task; then no prerequisite chain loops back on itself.
void validate(const Curriculum& curriculum);

}  // namespace incise::curriculum
