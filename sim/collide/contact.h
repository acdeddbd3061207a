#pragma once

// One contact between a tool shape and a triangulated surface (deformable tissue or a bone).

#include "sim/core/types.h"

namespace incise::sim::collide {

struct Contact {
  Vec3 point = Vec3::Zero();        // the contact point on the surface [m]
  Vec3 normal = Vec3::Zero();       // unit, out of the surface: from the tissue/bone to the tool
  Real depth = 0;                   // penetration along normal [m], > 0 when touching
  int triangle = -1;                // the surface triangle hit (its index in the surface)
  Vec3 barycentric = Vec3::Zero();  // point = sum_k barycentric[k] * corner k of that triangle
};

}  // namespace incise::sim::collide
