#pragma once

// Input checks shared by the contact, probe and force-model parts (internal to sim/tools; not a
// public header). Each throws std::invalid_argument naming the caller and the bad value.

#include "sim/collide/tool_shapes.h"
#include "sim/core/types.h"

namespace incise::sim::tools::checks {

void check_vector(const Vec3& value, const char* where, const char* what);
void check_radius(Real radius, const char* where);
void check_sphere(const collide::Sphere& sphere, const char* where);
void check_capsule(const collide::Capsule& capsule, const char* where);

}  // namespace incise::sim::tools::checks
