#pragma once

// Whether a point lies inside a closed surface held in a SurfaceBvh: the parity of the surface's
// crossings by a ray from the point. The tissue's boundary is closed whatever cuts and refinement
// did to it (it is the boundary of a tet mesh), so the parity is well defined.

#include <vector>

#include "sim/collide/surface_bvh.h"
#include "sim/core/types.h"

namespace incise::sim::collide {

// Whether p is inside the closed surface of bvh over positions x. The ray runs in a fixed, skew
// direction (no axis-aligned mesh edge or face lies along it) far enough to leave any organ, and
// each triangle it crosses counts once. scratch holds the triangles near the ray (kept by the
// caller, so that a steady caller allocates nothing).
bool inside_closed_surface(const SurfaceBvh& bvh, const Points& x, const Vec3& p,
                           std::vector<int>& scratch);

}  // namespace incise::sim::collide
