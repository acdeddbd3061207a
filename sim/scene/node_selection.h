#pragma once

#include <vector>

#include "sim/core/types.h"

namespace incise::sim {

// The tolerance [m] by which selection boxes are widened: 1e-6 of the diagonal of the points'
// bounding box, so that a box drawn exactly on a mesh face picks the face's nodes despite
// round-off in their coordinates, while staying far below any element size.
Real selection_tolerance(const Points& points);

// Indices (increasing) of the points inside box widened by tolerance on every side:
// box.min - tolerance <= p <= box.max + tolerance component-wise.
//   points  #nodes by 3 positions [m]
std::vector<int> nodes_in_box(const Points& points, const Box3& box, Real tolerance);

}  // namespace incise::sim
