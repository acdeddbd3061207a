#pragma once
// Internal to SurgicalScene (sim/surgery/surgical_scene*.cpp): the condensed far field of a
// scene (FarFieldSpec) at construction.

#include <vector>

#include "sim/surgery/surgical_scene.h"

namespace incise::sim::surgery {

struct FarFieldSetup {
  std::vector<char> far;  // per tissue tet: 1 in the far field
  Real guard = 0;         // [m], how near the far field a blade may come (FarFieldSpec)
  ModelFactory model;     // the hybrid condensed model, spec.model's in the operational region
};

// For spec.far_field.enabled: the far field's tets, with spec.tissue's nodes (and spec.fixed)
// renumbered far field first, the blade's guard and the model. Throws std::invalid_argument
// (require) if no tet lies outside or none inside the region, for fixed of the wrong size, or
// without a model factory.
FarFieldSetup set_up_far_field(SurgicalSceneSpec& spec);

}  // namespace incise::sim::surgery
