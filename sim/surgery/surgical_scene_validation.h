#pragma once
// Internal to SurgicalScene (sim/surgery/surgical_scene*.cpp): the checks of a SurgicalSceneSpec.

#include <string>

#include "sim/surgery/surgical_scene.h"

namespace incise::sim::surgery {

// Throws std::invalid_argument("surgical scene: " + what) unless ok.
void require(bool ok, const std::string& what);

// Throws std::invalid_argument naming the first field of spec out of its range (surgical_scene.h).
void validate(const SurgicalSceneSpec& spec);

}  // namespace incise::sim::surgery
