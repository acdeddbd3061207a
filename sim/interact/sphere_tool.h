#pragma once

#include "sim/core/types.h"

namespace incise::sim {

// A spherical tool tip (a probe) that pushes tissue surface nodes out of it with a penalty force
// (sim/interact/tool_contact.h). The scene's "tool" member; defaults suit a 1 cm probe on soft
// tissue.
struct SphereTool {
  Real radius = 0.005;   // "radius" [m], > 0
  Real stiffness = 300;  // "stiffness": penalty per node in contact [N/m], > 0
  Real damping = 0;      // "damping": normal damping per node in contact [N s/m], >= 0
};

}  // namespace incise::sim
